"""The page of ``spurdyn report``: one self-contained HTML file and its ``report.json``.

Figures are PNGs drawn with Matplotlib and inlined as base64 ``data:`` URIs; the style
sheet is inline too, with a print style (A4, no page break inside a table or figure),
so the page needs no network and prints cleanly to PDF from a browser. Numbers are
those of :func:`spurdyn.cli.design_data.gather`, formatted only.
"""

from __future__ import annotations

import base64
import html
import io
import json
from pathlib import Path
from typing import Any, Sequence

from spurdyn.sweep.store import write_text_atomic

CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;max-width:60rem;
margin:1.5rem auto;padding:0 1rem;color:#222;line-height:1.35}
h1{font-size:1.6rem;margin-bottom:.2rem}h2{font-size:1.2rem;border-bottom:1px solid #bbb;
margin-top:1.6rem}table{border-collapse:collapse;margin:.4rem 0;font-size:.9rem}
td,th{border:1px solid #ccc;padding:.15rem .45rem;text-align:right}th{background:#f2f2f2}
td.l,th.l{text-align:left}.warn{color:#a40000}.ok{color:#1a6b1a}.muted{color:#666}
img{max-width:100%}pre{background:#f6f6f6;padding:.5rem;font-size:.8rem;overflow-x:auto}
@media print{body{max-width:none;margin:0}h2{break-after:avoid}
table,figure,img,pre{break-inside:avoid}@page{size:A4;margin:15mm}}
"""


def esc(value: Any) -> str:
    return html.escape(str(value))


def num(value: Any, fmt: str = ".4g", scale: float = 1.0) -> str:
    """A number formatted, or an em dash where it is absent."""
    if value is None:
        return "&mdash;"
    text = format(value if scale == 1.0 else value * scale, fmt)
    return text[1:] if text.startswith("-") and not text.strip("-0.,") else text  # no "-0.00"


def table(head: Sequence[str], rows: Sequence[Sequence[Any]], left: int = 1) -> str:
    """An HTML table; the first ``left`` columns left-aligned (cells are HTML already)."""
    def cells(tag: str, row: Sequence[Any]) -> str:
        return "".join(f"<{tag}{' class=l' if i < left else ''}>{c}</{tag}>"
                       for i, c in enumerate(row))
    body = "".join(f"<tr>{cells('td', r)}</tr>" for r in rows)
    return f"<table><tr>{cells('th', head)}</tr>{body}</table>"


def png_uri(fig: Any) -> str:
    """A Matplotlib figure as an inline PNG (``data:`` URI); the figure is closed."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def file_uri(path: Path) -> str:
    return "data:image/png;base64," + base64.b64encode(path.read_bytes()).decode("ascii")


def img(uri: str | None, alt: str) -> str:
    return "" if uri is None else f'<figure><img src="{uri}" alt="{esc(alt)}"></figure>'


def speed_figure(data: dict[str, Any]) -> str | None:
    """Four panels against speed, a line per torque: dynamic factor (ISO's K_v dashed, the
    lumped model's dotted), transmission error, peak stresses, the model's safety factors;
    resonances marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pts = data["speed"]["points"]
    if not any(p["dynamic_factor"] is not None for p in pts):
        return None
    fig, ax = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    res = data["verdict"]["resonance"]
    for j, tq in enumerate(data["torques_Nm"]):
        mine = [p for p in pts if p["torque_Nm"] == tq]
        rpm = [p["rpm"] for p in mine]
        c = f"C{j}"

        def col(key: str, gear: int | None = None, scale: float = 1.0) -> list[float]:
            out = []
            for p in mine:
                v = p[key] if gear is None or p[key] is None else p[key][gear]
                out.append(float("nan") if v is None else v * scale)
            return out
        ax[0, 0].plot(rpm, col("dynamic_factor"), "o-", color=c, label=f"model, {tq:g} N m")
        kv = data["speed"]["iso_k_v"]
        if kv is not None:
            ax[0, 0].plot(data["rpm"], [float("nan") if r[j] is None else r[j] for r in kv],
                          "--", color=c, label=f"ISO 6336-1 K_v, {tq:g} N m")
        lumped = [q for q in data["speed"]["lumped"].get("points", []) if q["torque_Nm"] == tq]
        if any(q["dynamic_factor"] is not None for q in lumped):
            ax[0, 0].plot([q["rpm"] for q in lumped], [float("nan") if q["dynamic_factor"] is None
                                                       else q["dynamic_factor"] for q in lumped],
                          "x:", color=c, label=f"lumped model, {tq:g} N m")
        ax[0, 1].plot(rpm, col("transmission_error_rms_m", scale=1e6), "o-", color=c,
                      label=f"RMS, {tq:g} N m")
        ax[0, 1].plot(rpm, col("transmission_error_pp_m", scale=1e6), "s:", color=c,
                      label=f"peak-to-peak, {tq:g} N m")
        for g, mark in ((0, "o-"), (1, "s-")):
            ax[1, 0].plot(rpm, col("root_stress_max_Pa", g, 1e-6), mark, color=c,
                          label=f"root {'AB'[g]}, {tq:g} N m")
            ax[1, 1].plot(rpm, col("safety_root_model", g), mark, color=c,
                          label=f"S_F {'AB'[g]}, {tq:g} N m")
        ax[1, 0].plot(rpm, col("contact_pressure_max_Pa", scale=1e-6), "^--", color=c,
                      label=f"contact pressure, {tq:g} N m")
        ax[1, 1].plot(rpm, col("safety_contact_model", 0), "^--", color=c,
                      label=f"S_H A, {tq:g} N m")
    _mark_resonances(ax, res, min(data["rpm"]), max(data["rpm"]))
    ax[0, 0].set_ylabel("dynamic factor")
    ax[0, 1].set_ylabel("transmission error (um)")
    ax[1, 0].set_ylabel("peak stress (MPa)")
    ax[1, 1].set_ylabel("safety factor (model)")
    for a in ax[1]:
        a.set_xlabel("speed of gear A (rpm)")
    fig.suptitle("sector model, settled steady states; the lumped model on the sector's mesh "
                 "cycle beside (x, dotted)\ngrey lines: main resonance speeds, solid the "
                 "model's, dashed ISO's; dotted 1/k: super-harmonic ones", fontsize=9)
    return png_uri(fig)


def _mark_resonances(ax: Any, res: dict[str, Any], lo: float, hi: float) -> None:
    """The main resonance speeds on every panel (grey, solid the model's, dashed ISO's)
    where near the range ``lo``-``hi``, the super-harmonic ones (dotted, ``1/k``) on the
    dynamic factor's where in it; a grid and a legend on every panel."""
    for a in ax.flat:
        for name, style in (("model_rpm", "-"), ("iso_rpm", "--")):
            r = res.get(name)
            if r is not None and lo * 0.75 <= r <= hi * 1.25:
                a.axvline(r, color="0.4", ls=style, lw=1)
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    for k, r in res.get("superharmonic_rpm", {}).items():
        if lo <= r <= hi:   # the mesh frequency's k-th harmonic at f_n
            ax[0, 0].axvline(r, color="0.6", ls=":", lw=1)
            ax[0, 0].annotate(f"1/{k}", (r, 1), xycoords=("data", "axes fraction"),
                              xytext=(2, -10), textcoords="offset points", fontsize=7,
                              color="0.4")


def _where(m: dict[str, Any] | None, fmt: str = ".3f") -> str:
    if m is None:
        return "&mdash; (not computed)"
    return f"<b>{num(m['value'], fmt)}</b> at {m['rpm']:,.6g} rpm, {m['torque_Nm']:g} N m"


def verdict_part(data: dict[str, Any]) -> str:
    v = data["verdict"]
    rows = [["largest dynamic factor", _where(v["dynamic_factor_max"]),
             "summary.json dynamic_factor"]]
    for key, label in (("safety_root_model", "smallest S_F, model"),
                       ("safety_root_iso", "smallest S_F, ISO 6336-3"),
                       ("safety_contact_model", "smallest S_H, model"),
                       ("safety_contact_iso", "smallest S_H, ISO 6336-2")):
        for g in "AB":
            rows.append([f"{label}, gear {g}", _where(v[f"{key}_min"][g], ".2f"),
                         f"summary.json {key}"])
    res = v["resonance"]
    rows.append(["mesh resonance, model", f"{num(res['model_rpm'], ',.0f')} rpm "
                 f"({res['model_place'] or '&mdash;'})", "f_n of the mean mesh stiffness"])
    rows.append(["mesh resonance, ISO 6336-1", f"{num(res['iso_rpm'], ',.0f')} rpm "
                 f"({res['iso_place'] or 'ISO does not apply'})", "n_E1, method B"])
    sup = ", ".join(f"{num(r, ',.0f')} (1/{k})" for k, r in res["superharmonic_rpm"].items())
    ring = res.get("ring")
    where = ("k-th mesh harmonic at f_n (no ring read)" if ring is None else
             f"k-th mesh harmonic at the ring read at {ring['rpm']:,.6g} rpm, "
             f"{num(ring['mean_hz'], ',.0f')} Hz")
    rows.append(["super-harmonic resonances, model", f"{sup} rpm", esc(where)])
    if "dynamic_factor_max_lumped" in v:
        rows.insert(1, ["largest dynamic factor, lumped model beside",
                        _where(v["dynamic_factor_max_lumped"]), "its point records"])
    warn = "".join(f"<li class=warn>{esc(w)}</li>" for w in v["warnings"])
    words = (f"<ul>{warn}</ul>" if warn else
             "<p class=ok>No warning: every point complete and settled, no contact loss, "
             "no safety factor below 1, no resonance in or near the range, the largest "
             "dynamic factor inside the range.</p>")
    return "<h2>1. Verdict</h2>" + table(["figure", "value", "source"], rows, left=3) + words


def inputs_part(data: dict[str, Any]) -> str:
    i = data["inputs"]
    text = (f"<p>Case file <code>{esc(i['case_file'])}</code>:</p><pre>{esc(i['case_text'])}</pre>"
            if i["case_text"] is not None else "<p>A preset case (no file).</p>")
    rows = [[f"<code>{esc(s['key'])}</code>", esc(s["value"]),
             esc(s["source"])] for s in i["settings"]]
    damp = [[k.replace("_", " "), esc(", ".join(f"{a} {b:.4g}" if isinstance(b, float) else
                                                f"{a}: {b}" for a, b in v.items()))]
            for k, v in i["damping"].items() if v is not None]
    inert = i.get("disk_inertia_source") or {}
    damp += [[f"disk inertia {g.upper()}", esc(s)] for g, s in inert.items()]
    cmds = "\n".join(esc(c) for c in i["commands"])
    return ("<h2>2. Inputs</h2>" + text + "<p>Every setting of the run, given or taken by "
            "default:</p>" + table(["setting", "value", "source"], rows, left=3)
            + table(["taken by the model", "value and source"], damp, left=2)
            + f"<p>spurdyn {esc(i['version'])}. The commands that reproduce every figure:</p>"
            f"<pre>{cmds}</pre>")


def geometry_part(data: dict[str, Any], mesh_uri: str | None) -> str:
    g = data["geometry"]
    per = [("teeth", "teeth", "d", 1), ("pitch radius (mm)", "pitch_radius_m", ".4f", 1e3),
           ("base radius (mm)", "base_radius_m", ".4f", 1e3),
           ("tip radius (mm)", "tip_radius_m", ".4f", 1e3),
           ("root radius (mm)", "root_radius_m", ".4f", 1e3),
           ("profile shift x", "profile_shift", ".4f", 1),
           ("working pitch radius (mm)", "working_pitch_radius_m", ".4f", 1e3)]
    rows = [[label, num(g[k]["a"], f, s), num(g[k]["b"], f, s)] for label, k, f, s in per]
    pair = [["module (mm)", num(g["module_m"], ".4g", 1e3)],
            ["pressure angle / working (deg)", f"{num(g['pressure_angle_deg'])} / "
             f"{num(g['working_pressure_angle_deg'])}"],
            ["centre distance (mm)", num(g["centre_distance_m"], ".4f", 1e3)],
            ["contact ratio", num(g["contact_ratio"], ".4f")],
            ["backlash circumferential / normal (um)",
             f"{num(g['backlash_circumferential_m'], '.2f', 1e6)} / "
             f"{num(g['backlash_normal_m'], '.2f', 1e6)}"],
            ["driver", esc(g["driver"].upper())]]
    return ("<h2>3. Geometry</h2>" + table(["", "gear A", "gear B"], rows)
            + table(["pair", ""], pair) + img(mesh_uri, "the meshed teeth at the pitch point"))


def cycle_part(data: dict[str, Any], cycle_uri: str | None) -> str:
    mc = data["mesh_cycle"]
    if "absent" in mc:
        return f"<h2>4. Quasi-static mesh cycle</h2><p class=muted>{esc(mc['absent'])}</p>"
    rows = [[f"{r['torque_Nm']:g}", num(r["mesh_stiffness_mean_N_per_m"], ".1f", 1e-6),
             num(r["mesh_stiffness_min_N_per_m"], ".1f", 1e-6),
             num(r["mesh_stiffness_max_N_per_m"], ".1f", 1e-6),
             num(r["single_pair_stiffness_max_N_per_m"], ".1f", 1e-6),
             num(r.get("iso6336_single_pair_N_per_m"), ".1f", 1e-6),
             num(r.get("iso6336_mesh_N_per_m"), ".1f", 1e-6),
             num(r["transmission_error_pp_m"], ".3f", 1e6)] for r in mc["torques"]]
    head = ["torque (N m)", "k mean", "k min", "k max", "single pair max", "ISO c'b",
            "ISO c_γα b", "static TE p-p (um)"]
    return ("<h2>4. Quasi-static mesh cycle</h2><p>Sector model, loaded tooth contact "
            "analysis over one mesh cycle (stiffness in N/um; <code>spurdyn stiffness</code>)."
            "</p>" + table(head, rows) + img(cycle_uri, "mesh stiffness, static TE, load share"))


def speed_part(data: dict[str, Any], speed_uri: str | None) -> str:
    def pair(v: Any, fmt: str, s: float = 1.0) -> str:
        return "&mdash;" if v is None else " / ".join(num(x, fmt, s) for x in v)
    lumped = {(q["rpm"], q["torque_Nm"]): q["dynamic_factor"]
              for q in data["speed"]["lumped"].get("points", [])}
    rows = []
    for p in data["speed"]["points"]:
        st = p["status"] if p["status"] == "complete" else \
            f"<span class=warn>{esc(p['status'])}: {esc(p['reason'])}</span>"
        rows.append([f"{p['rpm']:,.6g}", f"{p['torque_Nm']:g}", st,
                     num(p["dynamic_factor"], ".3f"),
                     num(lumped.get((p["rpm"], p["torque_Nm"])), ".3f"),
                     num(p["iso6336_k_v"], ".3f"),
                     num(p["transmission_error_rms_m"], ".3f", 1e6),
                     num(p["transmission_error_pp_m"], ".3f", 1e6),
                     pair(p["root_stress_max_Pa"], ".1f", 1e-6),
                     num(p["contact_pressure_max_Pa"], ".0f", 1e-6),
                     pair(p["safety_root_model"], ".2f"), pair(p["safety_contact_model"], ".2f"),
                     "&mdash;" if p["settled"] is None else ("yes" if p["settled"] else
                                                             "<span class=warn>no</span>")])
    head = ["rpm A", "N m", "status", "K model", "K lumped", "ISO K_v", "TE rms (um)",
            "TE p-p (um)",
            "root σ A / B (MPa)", "p max (MPa)", "S_F A / B", "S_H A / B", "settled"]
    lp = data["speed"]["lumped"]
    note = (f"<p class=muted>No lumped model beside: {esc(lp['absent'])}.</p>" if "absent" in lp
            else "<p class=muted>K lumped: the lumped model (two disks and the mesh spring) on "
            "the sector model's quasi-static mesh cycle, with the same mesh damping ratio "
            f"({num(lp['settings']['damping_ratio'], '.3g')}) and cycles ("
            f"{lp['settings']['cycles']}, at most {lp['settings']['max_cycles']}); what the "
            "two differ by is the bodies' elasticity and inertia beyond the mesh spring.</p>")
    return ("<h2>5. Against speed</h2>" + img(speed_uri, "figures against speed") + note
            + table(head, rows, left=0))


def rating_part(data: dict[str, Any]) -> str:
    if not data["rating"]:
        return ("<h2>6. Rating</h2><p class=muted>No ISO 6336 rating: the materials carry no "
                "strengths (give material_class, grade and hardness).</p>")
    out = ["<h2>6. Rating (ISO 6336 method B)</h2>"]
    for r in data["rating"]:
        chain = r["rating_iso"]
        rows = [[esc(k), esc(v if not isinstance(v, float) else f"{v:.5g}")
                 if not isinstance(v, list) else
                 " / ".join(f"{x:.5g}" if isinstance(x, float) else esc(x) for x in v)]
                for k, v in chain.items() if k != "note"]
        out.append(f"<p>{r['torque_Nm']:g} N m at {r['rpm']:,.6g} rpm (the speed of its "
                   f"smallest S_F; <code>{esc(r['summary'])}</code>):</p>"
                   + table(["factor", "value (A / B)"], rows, left=2)
                   + f"<p class=muted>{esc(chain.get('note', ''))}</p>")
    return "".join(out)


def limits_part(data: dict[str, Any]) -> str:
    m = data["limits"]
    items = "".join(f"<li>{esc(x)}</li>" for x in m["limits"])
    pages = ", ".join(f"<code>docs/{esc(p)}</code>" for p in m["validation_pages"])
    return (f"<h2>7. Model and limits</h2><p>Model: {esc(m['model'])} (whole gears on "
            f"elastic rims, modal bodies, Hertzian strip contact, mesh damper, settled steady "
            f"state); tooth mesh {esc(m['mesh'])} Q8 elements per tooth, "
            f"{num(m['n_dof'], ',d')} degrees of freedom.</p><ul>{items}</ul>"
            f"<p>Validation pages (in the source tree): {pages}.</p>")


def render(data: dict[str, Any], pictures: dict[str, str | None]) -> str:
    """The whole page."""
    title = f"spurdyn design report: {data['case']}"
    body = "".join([
        f"<h1>{esc(title)}</h1><p class=muted>{esc(data['model'])} model, speeds "
        f"{min(data['rpm']):,.6g} to {max(data['rpm']):,.6g} rpm of gear A, torques "
        f"{', '.join(f'{t:g}' for t in data['torques_Nm'])} N m; spurdyn "
        f"{esc(data['version'])}. Every number is in report.json.</p>",
        verdict_part(data), inputs_part(data), geometry_part(data, pictures.get("mesh")),
        cycle_part(data, pictures.get("cycle")), speed_part(data, speed_figure(data)),
        rating_part(data), limits_part(data)])
    return (f"<!DOCTYPE html><html lang=en><head><meta charset=utf-8><title>{esc(title)}"
            f"</title><style>{CSS}</style></head><body>{body}</body></html>\n")


def write_report(out: Path, data: dict[str, Any]) -> tuple[Path, Path]:
    """Write ``report.html`` and ``report.json`` into ``out``; their paths."""
    pictures = data.pop("_pictures", {})
    out.mkdir(parents=True, exist_ok=True)
    js = out / "report.json"
    write_text_atomic(js, json.dumps(data, indent=1, allow_nan=False) + "\n")
    page = out / "report.html"
    write_text_atomic(page, render(data, pictures))
    return page, js


__all__ = ["render", "write_report"]
