"""``spurdyn report``: its numbers equal the results they came from, the page is one
self-contained file, a repeated report reuses its points, a failed point is shown and the
rest still written, bad input is refused before any point runs; and the page checked in a
real browser (headless Chromium, skipped where none is installed).

The points are real sector-model runs of the 23/47 example on a coarse 2 x 8 tooth mesh,
and the lumped model's beside them, run in this process (the local Dask cluster replaced
by the serial backend, as test_sweep.py does), two speeds and one torque.
"""

from __future__ import annotations

import base64
import json
import shutil
from contextlib import contextmanager
from html.parser import HTMLParser
from pathlib import Path

import pytest

from spurdyn.cli import sweep as cli_sweep
from spurdyn.cli.main import main
from spurdyn.sweep import point as point_mod
from spurdyn.sweep.backends import SerialBackend

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "pinion_23_47.toml"
ARGS = ["--mesh", "2x8", "--rpm", "2000,4000", "--jobs", "1"]
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@contextmanager
def serial_cluster():
    """The points run in this process (the local cluster's seam replaced)."""
    with pytest.MonkeyPatch.context() as mp:
        @contextmanager
        def local(jobs):
            yield SerialBackend()

        mp.setattr(cli_sweep, "local_backend", local)
        yield mp


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """One report of two speeds (exit status, stderr, folder)."""
    out = tmp_path_factory.mktemp("report") / "rep"
    with serial_cluster():
        code = main(["report", str(EXAMPLE), *ARGS, "--out", str(out)])
    return code, out


class Page(HTMLParser):
    """The tags and attributes of a page."""

    def __init__(self) -> None:
        super().__init__()
        self.attrs: list[tuple[str, str, str]] = []

    def handle_starttag(self, tag, attrs):
        self.attrs += [(tag, k, v or "") for k, v in attrs]


@pytest.mark.slow
def test_numbers_equal_their_sources(report):
    from spurdyn.case.file import load_case
    from spurdyn.iso6336.rating import iso_pair, rate

    code, out = report
    assert code == 0
    data = json.loads((out / "report.json").read_text())
    points = data["speed"]["points"]
    assert [p["rpm"] for p in points] == [2000.0, 4000.0]
    for p in points:
        s = json.loads((out / p["summary"]).read_text())
        assert p["status"] == s["status"] == "complete"
        for key in ("dynamic_factor", "settled", "transmission_error_rms_m",
                    "transmission_error_pp_m", "root_stress_max_Pa", "contact_pressure_max_Pa",
                    "safety_root_model", "safety_root_iso", "safety_contact_model",
                    "safety_contact_iso", "iso6336_k_v", "separations"):
            assert p[key] == s[key], key
        assert s["speed_a_rpm"] == pytest.approx(p["rpm"], rel=1e-12)
    v = data["verdict"]
    top = max(points, key=lambda p: p["dynamic_factor"])
    assert v["dynamic_factor_max"] == {"value": top["dynamic_factor"], "rpm": top["rpm"],
                                       "torque_Nm": 50.0}
    at_top = [w for w in v["warnings"] if "top of the range" in w]
    assert len(at_top) == (top["rpm"] == 4000.0)
    for key in ("safety_root_model", "safety_root_iso", "safety_contact_model",
                "safety_contact_iso"):
        for i, g in enumerate("AB"):
            assert v[f"{key}_min"][g]["value"] == min(p[key][i] for p in points)
    case = load_case(str(EXAMPLE))
    assert data["geometry"]["contact_ratio"] == case.pair.contact_ratio
    r = rate(iso_pair(case.pair), 50.0)
    row = data["mesh_cycle"]["torques"][0]
    assert row["iso6336_mesh_N_per_m"] == pytest.approx(r.mesh * case.pair.gear_a.face_width,
                                                        rel=1e-12)
    assert 0 < row["mesh_stiffness_mean_N_per_m"]
    rated = data["rating"][0]
    s = json.loads((out / rated["summary"]).read_text())
    assert rated["rating_iso"] == s["rating_iso"]
    assert min(rated["rating_iso"]["S_F"]) == min(min(p["safety_root_iso"]) for p in points)
    given = {x["key"]: x["source"] for x in data["inputs"]["settings"]}
    assert given["gear_a.teeth"] == "given" and given["mesh.nx"] == "given (--mesh)"
    assert given["gear_a.addendum"].startswith("default")


@pytest.mark.slow
def test_lumped_model_beside(report):
    """The lumped model ran at the same speeds and torques on the sector model's mesh cycle
    with the sector run's damping ratio and cycles; each of its numbers equals its point
    record's, and the verdict's largest lumped factor is theirs."""
    from spurdyn.sector.rules import DEFAULT_CYCLES, MESH_DAMPING_RATIO

    _, out = report
    data = json.loads((out / "report.json").read_text())
    lumped = data["speed"]["lumped"]
    assert lumped["settings"] == {"stiffness": "sector", "damping_ratio": MESH_DAMPING_RATIO,
                                  "cycles": DEFAULT_CYCLES, "max_cycles": 4 * DEFAULT_CYCLES,
                                  "mesh": "2x8"}
    assert [(p["rpm"], p["torque_Nm"]) for p in lumped["points"]] == \
        [(p["rpm"], p["torque_Nm"]) for p in data["speed"]["points"]]
    for p in lumped["points"]:
        record = json.loads((out / p["record"]).read_text())
        assert record["model"] == "lumped" and p["status"] == record["status"] == "complete"
        assert record["rpm"] == p["rpm"] and record["torque"] == p["torque_Nm"]
        for key, src in (("dynamic_factor", "dynamic_factor"), ("separations", "separations"),
                         ("transmission_error_rms_m", "transmission_error_rms"),
                         ("transmission_error_pp_m", "transmission_error_pp"),
                         ("cycles_done", "cycles_done")):
            assert p[key] == record[src], key
        assert p["settled"] is bool(record["settled"])
    top = max(lumped["points"], key=lambda p: p["dynamic_factor"])
    assert data["verdict"]["dynamic_factor_max_lumped"]["value"] == top["dynamic_factor"]
    res = data["verdict"]["resonance"]
    base = res["model_rpm"] if res["ring"] is None else res["ring"]["resonance_rpm"]
    assert res["superharmonic_rpm"] == {str(k): base / k for k in (2, 3, 4)}


def test_warnings_grouped_per_torque():
    """Points not settled, or with contact lost, make one warning per torque naming their
    speeds and the most cycles (losses); a failed point one of its own."""
    from types import SimpleNamespace

    from spurdyn.cli.design_data import verdict

    def row(rpm, tq, settled=True, cycles=5, seps=0, status="complete"):
        return {"rpm": rpm, "torque_Nm": tq, "status": status, "reason": "", "settled": settled,
                "cycles_done": cycles, "separations": seps, "dynamic_factor": 1.2,
                **{k: [2.0, 2.0] for k in ("safety_root_model", "safety_root_iso",
                                           "safety_contact_model", "safety_contact_iso")}}
    rows = [row(1000, 25), row(2000, 25, False, 20, 3), row(3000, 25, False, 18, 7),
            row(2000, 50, seps=1), row(3000, 50, status="failed")]
    res = SimpleNamespace(resonance_rpm=1e5, natural_frequency_hz=1.0, iso_resonance_rpm=None)
    w = verdict(rows, res, (1000.0, 2000.0, 3000.0))["warnings"]
    assert w[0] == "3000 rpm, 50 N m: failed"
    assert w[1].startswith("not settled after 20 mesh cycles at 2,000, 3,000 rpm (25 N m)")
    assert w[2] == "contact lost up to 7 times a run (rattle) at 2,000, 3,000 rpm (25 N m)"
    assert w[3] == "contact lost up to 1 times a run (rattle) at 2,000 rpm (50 N m)"
    assert len(w) == 4


def test_ring_frequencies_of_a_made_signal():
    """Damped rings of 8 kHz over single contact and 10 kHz over double, restarted at each
    change of pairs (a 23-tooth mesh at 1,000 rpm, contact ratio 1.48), are read back
    within 0.5 %, and the time-weighted mean is (2 - eps) f_1 + (eps - 1) f_2."""
    import numpy as np

    from spurdyn.cli.design_ring import mean_ring, zone_frequencies

    eps, period = 1.48, 60.0 / (23 * 1000.0)
    t = np.arange(0.0, 6 * period, 0.5e-6)
    phase = (t / period) % 1.0
    pairs = np.where(phase < eps - 1.0, 2, 1)
    start = t - np.where(phase < eps - 1.0, phase, phase - (eps - 1.0)) * period
    freq = np.where(pairs == 2, 10e3, 8e3)
    age = t - start
    force = 1000.0 + 50.0 * np.exp(-0.05 * 2 * np.pi * freq * age) * np.sin(2 * np.pi * freq * age)
    found = zone_frequencies(t, force, pairs, 1000.0)
    assert found[1] == pytest.approx(8e3, rel=5e-3) and found[2] == pytest.approx(10e3, rel=5e-3)
    assert mean_ring(found, eps) == pytest.approx(0.52 * found[1] + 0.48 * found[2], rel=1e-12)
    assert mean_ring(found, 2.1) is None and mean_ring({1: 8e3}, eps) is None


def test_default_speeds_reach_the_resonance():
    """The default --rpm: 20 speeds, a step of 1.3 times the resonance speed over 20 rounded
    to 50 rpm, so the top speed is 1.3 times it within 20 x 25 rpm."""
    from spurdyn.cli.design import default_rpm
    from spurdyn.sweep.spec import parse_speeds

    for n_res in (22055.4, 12276.0, 300.0, 10.0):
        rpms = parse_speeds(default_rpm(n_res))
        assert len(rpms) == 20 and rpms[0] == pytest.approx(rpms[1] - rpms[0])
        assert rpms[0] % 50 == 0 and rpms[0] >= 50
        if n_res > 1000:
            assert abs(rpms[-1] - 1.3 * n_res) <= 20 * 25
    assert default_rpm(22055.4) == "1450:29000/20"


@pytest.mark.slow
def test_page_is_self_contained(report):
    _, out = report
    text = (out / "report.html").read_text()
    page = Page()
    page.feed(text)
    imgs = [v for tag, k, v in page.attrs if tag == "img" and k == "src"]
    assert len(imgs) == 3                     # the teeth, the mesh cycle, against speed
    for src in imgs:
        head, payload = src.split(",", 1)
        assert head == "data:image/png;base64"
        assert base64.b64decode(payload)[:8] == PNG_MAGIC
    for tag, k, v in page.attrs:
        assert k not in ("src", "href") or not v.lower().startswith(("http:", "https:", "//")), (tag, v)
    assert "<script" not in text and "<link" not in text and "@media print" in text
    for part in ("1. Verdict", "2. Inputs", "3. Geometry", "4. Quasi-static mesh cycle",
                 "5. Against speed", "6. Rating", "7. Model and limits"):
        assert part in text


@pytest.mark.slow
def test_repeat_reuses_points_and_shows_a_failed_one(report, tmp_path, capsys):
    """A third speed whose run fails: the two finished points are not computed again, the
    failed one is on the page with its reason, the rest still written (exit status 1)."""
    _, first = report
    out = tmp_path / "rep"
    shutil.copytree(first, out)
    computed = []

    def failing(model, case):
        computed.append((model, case.run.speed_a))
        raise RuntimeError("the solver diverged (a test)")

    with serial_cluster() as mp:
        mp.setattr(point_mod, "simulate_model", failing)
        code = main(["report", str(EXAMPLE), *ARGS[:2], "--rpm", "2000,3000,4000",
                     "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 1 and sorted(m for m, _ in computed) == ["lumped", "sector"]  # one each
    assert "point 1/1 (3000 rpm, 50 N m): failed" in err          # a line per point
    data = json.loads((out / "report.json").read_text())
    bad = [p for p in data["speed"]["points"] if p["status"] != "complete"]
    assert [p["rpm"] for p in bad] == [3000.0] and bad[0]["status"] == "failed"
    assert "the solver diverged" in bad[0]["reason"] and bad[0]["dynamic_factor"] is None
    assert any("3000 rpm" in w and "failed" in w for w in data["verdict"]["warnings"])
    assert "the solver diverged (a test)" in (out / "report.html").read_text()
    lumped = [p for p in data["speed"]["lumped"]["points"] if p["status"] != "complete"]
    assert [p["rpm"] for p in lumped] == [3000.0] and lumped[0]["dynamic_factor"] is None


@pytest.mark.slow
def test_no_lumped(report, tmp_path):
    """--no-lumped: no lumped point runs (the sector's are reused), the page says why."""
    _, first = report
    out = tmp_path / "rep"
    shutil.copytree(first, out)
    shutil.rmtree(out / "sweep" / "points")       # no point may run: none is left to reuse
    shutil.copytree(first / "sweep" / "points", out / "sweep" / "points",
                    ignore=lambda d, names: [n for n in names if n.startswith("lumped")])
    with serial_cluster() as mp:
        mp.setattr(point_mod, "simulate_model", lambda *a: pytest.fail("a point ran"))
        code = main(["report", str(EXAMPLE), *ARGS, "--no-lumped", "--out", str(out)])
    assert code == 0
    data = json.loads((out / "report.json").read_text())
    assert data["speed"]["lumped"] == {"absent": "left out (--no-lumped)"}
    assert "dynamic_factor_max_lumped" not in data["verdict"]
    assert "No lumped model beside: left out (--no-lumped)" in (out / "report.html").read_text()


@pytest.mark.parametrize("extra, field", [
    (["--rpm", "abc"], "--rpm"),
    (["--rpm", "1000", "--torque", "-5"], "--torque"),
    (["--rpm", "1000", "--jobs", "0"], "--jobs"),
    (["--rpm", "1000", "--mesh", "2y8"], "--mesh"),
])
def test_bad_input_refused(tmp_path, capsys, extra, field):
    out = tmp_path / "rep"
    with serial_cluster() as mp:
        mp.setattr(point_mod, "simulate_model", lambda *a: pytest.fail("a point ran"))
        code = main(["report", str(EXAMPLE), *extra, "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and field in err[0], err
    assert not out.exists()


def test_bad_case_refused(tmp_path, capsys):
    case = tmp_path / "bad.toml"
    case.write_text(EXAMPLE.read_text().replace("face_width = 0.020", "face_widht = 0.020", 1))
    code = main(["report", str(case), "--rpm", "1000", "--out", str(tmp_path / "rep")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "face_widht" in err[0], err
    assert not (tmp_path / "rep").exists()
    (tmp_path / "file").write_text("x")
    assert main(["report", str(EXAMPLE), "--out", str(tmp_path / "file")]) == 2
    assert "--out" in capsys.readouterr().err


def _chromium() -> tuple[str, str] | None:
    for browser in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(browser)
        if path and shutil.which("chromedriver"):
            return path, shutil.which("chromedriver")
    return None


@pytest.mark.slow
def test_page_in_a_real_browser(report, tmp_path):
    """Every figure loaded (naturalWidth > 0), no error in the browser's console; a
    screenshot kept under tmp_path."""
    found = _chromium()
    if found is None:
        pytest.skip("no Chromium and chromedriver installed (Debian: apt-get install "
                    "chromium chromium-driver): the browser test did not run")
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed "
                                    "(pip install -e '.[test]'): the browser test did not run")
    from selenium.webdriver.chrome.service import Service

    _, out = report
    options = webdriver.ChromeOptions()
    options.binary_location = found[0]
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1280,2000",
                "--disable-dev-shm-usage"):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(found[1]), options=options)
    try:
        driver.get((out / "report.html").resolve().as_uri())
        widths = driver.execute_script(
            "return Array.from(document.images).map(i => i.complete ? i.naturalWidth : 0)")
        shot = tmp_path / "report.png"
        driver.save_screenshot(str(shot))
        logs = driver.get_log("browser")
    finally:
        driver.quit()
    assert len(widths) == 3 and all(w > 0 for w in widths), widths
    assert [e for e in logs if e["level"] in ("SEVERE", "ERROR")] == []
    assert shot.read_bytes()[:8] == PNG_MAGIC
