"""The study's report: a rich table for the terminal; report.csv, report.json and report.md."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

CSV_COLUMNS = ["case", "kind", "size", "ratio", "count", "state", "wall_s", "cpu_s", "peak_mib", "steps",
               "particles", "ale_elements", "solid_elements", "quantity", "l2", "peak", "peak_time", "peak_time_rel",
               "peak_value", "reference_peak"]


def _pct(v) -> str:
    return "-" if v is None or not isinstance(v, (int, float)) or not math.isfinite(v) else f"{100 * v:.2f}"


def _num(v, spec: str = ".3g") -> str:
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def csv_rows(result: dict) -> list[dict]:
    rows = []
    for r in result["cases"]:
        base = {k: r.get(k) for k in CSV_COLUMNS[:13]}
        if not r["errors"]:
            rows.append(base)
        for q, e in r["errors"].items():
            rows.append({**base, "quantity": q, **{k: e.get(k) for k in CSV_COLUMNS[14:]}})
    return rows


def table(result: dict):
    """A rich Table: one row per case, L2 error (%) per quantity."""
    from rich.table import Table

    t = Table(title=f"mesh study against {result['reference']} (L2 error %, peak error %)")
    for col in ("case", "N", "steps", "wall s", "cpu s", "peak MiB"):
        t.add_column(col, justify="left" if col == "case" else "right")
    for q in result["quantities"]:
        t.add_column(q, justify="right")
    for r in result["cases"]:
        cells = [r["case"] + (" (ref)" if r["reference"] else ""), str(r["count"]), _num(r.get("steps"), "d"),
                 _num(r.get("wall_s"), ".1f"), _num(r.get("cpu_s"), ".1f"), _num(r.get("peak_mib"), ".0f")]
        for q in result["quantities"]:
            e = r["errors"].get(q, {})
            cells.append(f"{_pct(e.get('l2'))} / {_pct(e.get('peak'))}" if "l2" in e else (r.get("state") or "-"))
        t.add_row(*cells)
    return t


def markdown(result: dict) -> str:
    q = result["quantities"]
    lines = [f"# Mesh study: {Path(result['deck']).name}", "",
             f"Reference: `{result['reference']}`. Tolerance {100 * result['tolerance']:g} % (normalised L2).", "",
             f"**Recommendation:** {result['recommendation']}", "", "## Cases", "",
             "| case | kind | spacing / size | ratio | N | steps | wall s | cpu s | peak MiB | state |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["cases"]:
        lines.append(f"| {r['case']}{' (ref)' if r['reference'] else ''} | {r['kind']} | {r['size']:.4g} | "
                     f"{r['ratio']:.3g} | {r['count']} | {_num(r.get('steps'), 'd')} | {_num(r.get('wall_s'), '.2f')} | "
                     f"{_num(r.get('cpu_s'), '.2f')} | {_num(r.get('peak_mib'), '.0f')} | {r.get('state')} |")
    lines += ["", "## Errors against the reference", "",
              "| case | quantity | L2 % | peak % | time of peak error | time of peak / duration % |",
              "|---|---|---|---|---|---|"]
    for r in result["cases"]:
        for name in q:
            e = r["errors"].get(name)
            if e and "l2" in e:
                lines.append(f"| {r['case']} | {name} | {_pct(e['l2'])} | {_pct(e['peak'])} | "
                             f"{_num(e['peak_time'])} | {_pct(e['peak_time_rel'])} |")
    lines += ["", "## Convergence (peak values, three finest levels)", ""]
    if not result["convergence"]:
        lines.append("Fewer than three finished levels of a kind: no observed order or GCI.")
    for kind, per_q in result["convergence"].items():
        lines += [f"### {kind.upper()}", "",
                  "| quantity | levels | observed order | Richardson value | GCI fine % | GCI medium % | asymptotic |",
                  "|---|---|---|---|---|---|---|"]
        for name, c in per_q.items():
            lines.append(f"| {name} | {', '.join(c['cases'])} | {_num(c['order'])} | {_num(c['extrapolated'], '.6g')} | "
                         f"{_pct(c['gci_fine'])} | {_pct(c['gci_medium'])} | {_num(c['asymptotic'])} |")
        lines.append("")
    p = result["prediction"]
    lines += ["## Cost model", ""]
    if p["cost_fit"]:
        lines.append(f"- wall time = {p['cost_fit'][0]:.3g} N^{p['cost_fit'][1]:.3f} (N particles)")
    if p["count_fit"]:
        lines.append(f"- N = {p['count_fit'][0]:.4g} ratio^{p['count_fit'][1]:.3f}")
    if p["error_fit"]:
        lines.append(f"- worst L2 error = {p['error_fit'][0]:.3g} ratio^{p['error_fit'][1]:.3f}")
    if p["ratio"] is not None:
        lines.append(f"- ratio for {100 * p['tolerance']:g} %: {p['ratio']:.3g}"
                     + (f", {p['particles']:.3g} particles, about {p['wall']:.3g} s" if p["wall"] is not None else ""))
    if not any((p["cost_fit"], p["error_fit"])):
        lines.append("Fewer than two finished SPH levels: no fit.")
    lines += ["", "## Plots", ""]
    for png in ("error_vs_ratio.png", "pareto.png"):
        lines.append(f"![{png}]({png})")
    for name in q:
        lines.append(f"![{name}](history_{name}.png)")
    return "\n".join(lines) + "\n"


def _finite(v):
    """NaN and infinities as null, so report.json is strict JSON."""
    if isinstance(v, float):
        return v if math.isfinite(v) else None
    if isinstance(v, dict):
        return {k: _finite(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_finite(x) for x in v]
    return v


def write_all(out: Path, result: dict) -> None:
    (out / "report.json").write_text(json.dumps(_finite(result), indent=2) + "\n")
    with (out / "report.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_COLUMNS, extrasaction="ignore")
        w.writeheader()
        w.writerows(csv_rows(result))
    (out / "report.md").write_text(markdown(result))
