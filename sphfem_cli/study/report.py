"""The study's report: a rich table for the terminal; report.csv, report.json and report.md.

Every format carries each failed case's message (CSV column ``message``, the Markdown table and
its Failures section, the JSON case rows) and the recommendation carries them too."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

CASE_COLUMNS = ["case", "method", "role", "size", "ratio", "count", "state", "cpu_s", "cpu_spread", "compile_s",
                "wall_s", "peak_mib", "steps", "particles", "ale_elements", "solid_elements", "message"]
ERROR_COLUMNS = ["l2", "peak", "peak_time", "peak_time_rel", "peak_value", "reference_peak"]
CSV_COLUMNS = CASE_COLUMNS + ["quantity", "compared"] + ERROR_COLUMNS + ["l2_below_reference_uncertainty",
                                                                         "peak_below_reference_uncertainty"]


def _ok(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _pct(v, spec: str = ".2f") -> str:
    return format(100 * v, spec) if _ok(v) else "-"


def _num(v, spec: str = ".3g") -> str:
    return format(v, spec) if _ok(v) else "-"


def _monotone(c: dict) -> str:
    """The monotone column of a convergence row: yes, yes but diverging, or not monotone."""
    if not c["monotone"]:
        return "**no: not monotone**"
    return "yes, **but the differences grow**" if c.get("diverging") else "yes"


def _one_line(text, width: int = 160) -> str:
    line = " ".join(str(text or "").split())
    return line if len(line) <= width else line[: width - 3] + "..."


def _flag(e: dict, key: str) -> str:
    b = (e.get("below_reference_uncertainty") or {}).get(key)
    return "" if b is None else ("*" if b else "")


def compared(result: dict, quantity: str) -> str:
    """How a quantity is compared: "raw samples" or its filter's description (result["filters"])."""
    f = (result.get("filters") or {}).get(quantity)
    return f["description"] if f else "raw samples"


def csv_rows(result: dict) -> list[dict]:
    rows = []
    for r in result["cases"]:
        base = {k: r.get(k) for k in CASE_COLUMNS}
        base["message"] = _one_line(base["message"], 2000) if base["message"] else ""
        if not r["errors"]:
            rows.append(base)
        for q, e in r["errors"].items():
            below = e.get("below_reference_uncertainty") or {}
            rows.append({**base, "quantity": q, "compared": compared(result, q), **{k: e.get(k) for k in ERROR_COLUMNS},
                         "l2_below_reference_uncertainty": below.get("l2"),
                         "peak_below_reference_uncertainty": below.get("peak")})
    return rows


def table(result: dict):
    """A rich Table: one row per case, L2 error / peak error (%) per quantity; * below the reference's uncertainty."""
    from rich.table import Table

    t = Table(title=f"mesh study against {result['reference']['label']} (L2 % / peak %; * below the reference's "
                    "own uncertainty)")
    for col in ("case", "N", "steps", "cpu s", "compile s", "peak MiB"):
        t.add_column(col, justify="left" if col == "case" else "right")
    for q in result["quantities"]:
        t.add_column(q, justify="right")
    for r in result["cases"]:
        cpu = _num(r.get("cpu_s"), ".2f") + (f" ±{_pct(r['cpu_spread'] / 2, '.0f')}%" if _ok(r.get("cpu_spread"))
                                             and len(r.get("cpu_runs") or []) > 1 else "")
        cells = [r["case"] + (" (ref)" if r["reference"] else "") + (" (verify)" if r["role"] == "verify" else ""),
                 str(r["count"]), _num(r.get("steps"), "d"), cpu, _num(r.get("compile_s"), ".1f"),
                 _num(r.get("peak_mib"), ".0f")]
        for q in result["quantities"]:
            e = r["errors"].get(q, {})
            cells.append(f"{_pct(e.get('l2'))}{_flag(e, 'l2')} / {_pct(e.get('peak'))}{_flag(e, 'peak')}"
                         if "l2" in e else (r.get("state") or "-"))
        t.add_row(*cells)
    return t


def _recommendation_md(rec: dict) -> list[str]:
    lines = ["## Recommendation", "", f"**{rec['text']}**", "",
             f"- verdict: {rec['verdict']}; ratio: {rec['ratio'] if rec['ratio'] is not None else '-'}; "
             f"tolerance {_pct(rec['tolerance'], 'g')} % (worst normalised L2 over the quantities)"]
    p = rec.get("predicted")
    if p:
        def iv(x, pct=False):
            if not x:
                return "no interval (exact fit)"
            return f"95 % [{_pct(x[0])}, {_pct(x[1])}] %" if pct else f"95 % [{_num(x[0])}, {_num(x[1])}]"
        lines += [f"- predicted: error {_pct(p['error'])} % ({iv(p['error_interval'], True)}), "
                  f"CPU {_num(p['cpu_s'])} s ({iv(p['cpu_interval'])}), {_num(p['particles'])} particles, "
                  f"{_num(p['steps'], '.0f')} steps, peak {_num(p['peak_mib'], '.0f')} MiB ({iv(p['peak_mib_interval'])})"]
    v = rec.get("verified")
    if v and v.get("measured"):
        m, e = v["measured"], v["prediction_error"]
        lines += [f"- verified by {v['case']}{' (a tested case, in the fit)' if v.get('in_fit') else ''}: measured "
                  f"error {_pct(m['error'])} %, CPU {_num(m['cpu_s'])} s, peak {_num(m['peak_mib'], '.0f')} MiB, "
                  f"{_num(m['steps'], 'd')} steps; prediction error (predicted - measured) / measured: error "
                  f"{_pct(e['error'], '+.1f')} %, CPU {_pct(e['cpu_s'], '+.1f')} %, memory {_pct(e['peak_mib'], '+.1f')} %, "
                  f"steps {_pct(e['steps'], '+.1f')} %"]
    if rec.get("verify_note"):
        lines.append(f"- {rec['verify_note']}")
    return lines + [""]


def markdown(result: dict) -> str:
    q = result["quantities"]
    ref = result["reference"]
    lines = [f"# Mesh study: {Path(result['deck']).name}", "",
             f"Reference: `{ref['label']}`" + (f" (the finest of {', '.join(ref['levels'])})" if ref["levels"] else "")
             + ".", ""]
    for f in ref["failed"]:
        lines.append(f"**The finer reference {f['case']} failed:** {_one_line(f['message'], 400)}")
        lines.append("")
    lines += _recommendation_md(result["recommendation"])
    for name in q:
        lines.append(f"- `{name}` compared as: {compared(result, name)}"
                     + (" (the same filter on every case and on the reference)" if (result.get("filters") or {}).get(name)
                        else ""))
    for note in result["plan_notes"]:
        lines.append(f"- {note}")
    for name, why in result["quantities_left_out"].items():
        lines.append(f"- `{name}` left out of the default quantities: {why}")
    lines += ["", "## Cases", "",
              "CPU: user + system seconds of the model build and run, numba compilation excluded (median over the "
              "repeats; spread = (max - min) / median); compile: seconds numba spent compiling, apart.", "",
              "| case | method | spacing / size | ratio | N | steps | cpu s | spread % | repeats | compile s | "
              "peak MiB | state | message |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["cases"]:
        lines.append(f"| {r['case']}{' (ref)' if r['reference'] else ''}{' (verify)' if r['role'] == 'verify' else ''} "
                     f"| {r['method']} | {r['size']:.4g} | {r['ratio']:.3g} | {r['count']} | {_num(r.get('steps'), 'd')} | "
                     f"{_num(r.get('cpu_s'), '.3f')} | {_pct(r.get('cpu_spread'), '.1f')} | {len(r.get('cpu_runs') or [])} | "
                     f"{_num(r.get('compile_s'), '.1f')} | {_num(r.get('peak_mib'), '.0f')} | {r.get('state')} | "
                     f"{_one_line(r.get('message'))} |")
    lines += ["", "## Reference uncertainty (peak values)", ""]
    if ref["uncertainty"]:
        lines += ["| quantity | method | levels | order | monotone | asymptotic | GCI % | L2 band % | Richardson value |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for name, u in ref["uncertainty"].items():
            mono = "-" if u["monotone"] is None else _monotone(u)
            lines.append(f"| {name} | {u['method']} | {', '.join(u['levels'])} | {_num(u['order'])} | {mono} | "
                         f"{_num(u['asymptotic'])} | {_pct(u['gci'])} | {_pct(u['l2'])} | {_num(u['extrapolated'], '.6g')} |")
    else:
        lines.append("No reference levels: its uncertainty is unknown.")
    lines += ["", "## Errors against the reference", "",
              "`*`: below the reference's own uncertainty (the reference cannot tell it from zero).", "",
              "| case | quantity | L2 % | peak % | time of peak error | time of peak / duration % |",
              "|---|---|---|---|---|---|"]
    for r in result["cases"]:
        for name in q:
            e = r["errors"].get(name)
            if e and "l2" in e:
                lines.append(f"| {r['case']} | {name} | {_pct(e['l2'])}{_flag(e, 'l2')} | {_pct(e['peak'])}"
                             f"{_flag(e, 'peak')} | {_num(e['peak_time'])} | {_pct(e['peak_time_rel'])} |")
    lines += ["", "## Convergence of each method (peak values, three finest levels)", "",
              "Asymptotic: GCI_medium / (r21^p GCI_fine), near 1 in the asymptotic range (within a factor 1.25 here; "
              "no check for levels that are not monotone).",
              ""]
    if not result["convergence"]:
        lines.append("Fewer than three finished levels of a kind: no observed order or GCI.")
    for kind, per_q in result["convergence"].items():
        lines += [f"### {kind.upper()}", "",
                  "| quantity | levels | monotone | observed order | Richardson value | GCI fine % | GCI medium % | "
                  "asymptotic | in range |", "|---|---|---|---|---|---|---|---|---|"]
        for name, c in per_q.items():
            a = c["asymptotic"]
            inside = "-" if not _ok(a) or not c["monotone"] else ("yes" if 0.8 <= a <= 1.25 else "**no**")
            lines.append(f"| {name} | {', '.join(c['cases'])} | {_monotone(c)} | "
                         f"{_num(c['order'])} | {_num(c['extrapolated'], '.6g')} | {_pct(c['gci_fine'])} | "
                         f"{_pct(c['gci_medium'])} | {_num(a)} | {inside} |")
        lines.append("")
    m = result["model"]
    lines += ["## Models", ""]
    e = m["error"]
    if e["form"]:
        lines.append(f"- error (the worst L2 over the quantities): the largest of the per-quantity models below; "
                     f"at ratio {_num(e['at_ratio'])} {e['governing']} governs; {e['reason']}")
    else:
        lines.append(f"- error: no model ({e['reason']})")
    for name, pq in m["error_per_quantity"].items():
        law = "e = e_inf + c r^-p" if pq["form"] == "floor" else "e = c r^-p"
        lines.append(f"  - {name}: {pq['form']}, {law}: e_inf = {_pct(pq['floor'])} %, c = {_num(pq['c'])}, "
                     f"p = {_num(pq['order'])}, relative residual {_pct(pq['residual'], '.2g')} %"
                     + ("" if pq["falls"] else f"; does not fall: counted as its largest, {_pct(pq['largest'])} %"))
    for label, block in (("SPH", m), ("ALE", m["ale"])):
        c, mem = block["cost"], block["memory"]
        if c["coefficients"]:
            lines.append(f"- {label} cost: {c['form']}: a = {_num(c['coefficients']['a'])} s, "
                         f"c = {_num(c['coefficients']['c'])} s per element- or particle-step, relative residual "
                         f"{_pct(c['residual'], '.2g')} % ({c['points']} cases)")
        if mem["coefficients"]:
            lines.append(f"- {label} memory: {mem['form']}: m0 = {_num(mem['coefficients']['m0'])} MiB, "
                         f"m1 = {_num(mem['coefficients']['m1'] * 1024)} KiB per element or particle")
    lines.append(f"- {m['steps']}")
    fails = result["recommendation"]["failures"]
    if fails:
        lines += ["", "## Failures", ""]
        lines += [f"- **{f['case']}**: {_one_line(f['message'], 2000)}" for f in fails]
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
