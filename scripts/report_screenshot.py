"""The README's picture of a design report: ``python scripts/report_screenshot.py``.

Makes a quick report of ``examples/pinion_23_47.toml`` (``spurdyn report``, the default
tooth mesh and speed range, 8 speeds, the case's torque, two local workers; about a
minute and a half on a 2-core machine, less when the folder already holds its points)
unless ``--report DIR`` names one made already, opens its ``report.html`` in headless
Chromium through Selenium (as ``tests/test_report.py`` does), and takes two views of the
page: its top (the verdict) and its part 5 (the figures against speed). The two are set
side by side, scaled to ``--width`` pixels and saved with a palette of 128 colours as
``docs/figures/report_page.png`` (about 200 KB). Needs Chromium and chromedriver
(Debian: ``apt-get install chromium chromium-driver``) and selenium (the test extras).
"""

from __future__ import annotations

import argparse
import io
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "examples" / "pinion_23_47.toml"
PNG = ROOT / "docs" / "figures" / "report_page.png"
#: The browser window (CSS pixels) each view is taken in.
WINDOW = (1100, 1250)
#: The quick report's speeds: 8 of the default range (spurdyn.cli.design.default_rpm).
SPEEDS = 8


def quick_report(out: Path) -> None:
    """``spurdyn report`` of the example into ``out`` (its points reused if there)."""
    sys.path.insert(0, str(ROOT / "src"))
    from spurdyn.cli.design import default_rpm
    from spurdyn.cli.sweep import resolve_sweep_case
    from spurdyn.sweep.resonance import resonance_estimate
    from spurdyn.sweep.spec import parse_speeds

    case = resolve_sweep_case(str(CASE), {}, {}, 1000.0)
    top = max(parse_speeds(default_rpm(resonance_estimate(case, "sector").resonance_rpm)))
    rpm = f"{top / SPEEDS:g}:{top:g}/{SPEEDS}"
    cmd = [sys.executable, "-c", "from spurdyn.cli.command import entry; entry()", "report",
           str(CASE.relative_to(ROOT)), "--rpm", rpm, "--jobs", "2", "--quiet", "--out",
           str(out.relative_to(ROOT))]
    print("spurdyn " + " ".join(cmd[3:]), flush=True)
    subprocess.run(cmd, check=False, cwd=ROOT,
                   env=dict(os.environ, PYTHONPATH=str(ROOT / "src")))
    if not (out / "report.html").is_file():
        sys.exit(f"no report.html in {out}")


def views(page: Path) -> list[bytes]:
    """PNG screenshots of the page's top and of its part 5 (the figures against speed)."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    browser = next((shutil.which(b) for b in ("chromium", "chromium-browser", "google-chrome")
                    if shutil.which(b)), None)
    driver_path = shutil.which("chromedriver")
    if browser is None or driver_path is None:
        sys.exit("no Chromium and chromedriver installed (Debian: apt-get install chromium "
                 "chromium-driver)")
    options = webdriver.ChromeOptions()
    options.binary_location = browser
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                f"--window-size={WINDOW[0]},{WINDOW[1]}", "--disable-dev-shm-usage"):
        options.add_argument(arg)
    driver = webdriver.Chrome(service=Service(driver_path), options=options)
    try:
        driver.get(page.resolve().as_uri())
        shots = [driver.get_screenshot_as_png()]
        driver.execute_script("Array.from(document.querySelectorAll('h2')).find("
                              "h => h.textContent.startsWith('5.')).scrollIntoView()")
        shots.append(driver.get_screenshot_as_png())
    finally:
        driver.quit()
    return shots


def compose(shots: list[bytes], width: int) -> bytes:
    """The views side by side with a grey rule between, scaled to ``width`` pixels wide,
    as a PNG of 128 colours."""
    from PIL import Image

    images = [Image.open(io.BytesIO(s)).convert("RGB") for s in shots]
    gap = 12
    w = sum(i.width for i in images) + gap * (len(images) - 1)
    h = max(i.height for i in images)
    sheet = Image.new("RGB", (w, h), (160, 160, 160))
    x = 0
    for i in images:
        sheet.paste(i, (x, 0))
        x += i.width + gap
    sheet = sheet.resize((width, round(h * width / w)), Image.LANCZOS)
    buf = io.BytesIO()
    sheet.quantize(colors=128, method=Image.Quantize.MEDIANCUT).save(buf, "PNG", optimize=True)
    return buf.getvalue()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--report", type=Path, help="a report folder made already "
                        "(default: make the quick report in out/report-screenshot)")
    parser.add_argument("--png", type=Path, default=PNG, help=f"the picture (default {PNG})")
    parser.add_argument("--width", type=int, default=1600, help="its width in pixels")
    args = parser.parse_args()
    folder = args.report
    if folder is None:
        folder = ROOT / "out" / "report-screenshot"
        quick_report(folder)
    data = compose(views(folder / "report.html"), args.width)
    args.png.write_bytes(data)
    print(f"-> {args.png} ({len(data) / 1024:.0f} KB)")


if __name__ == "__main__":
    main()
