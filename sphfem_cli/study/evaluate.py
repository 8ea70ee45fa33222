"""Evaluate a study: the reference and its own uncertainty, each case's errors against it, grid
convergence, the error / cost / memory models, and the recommendation (docs/mesh-study.md).

Reference uncertainty (per quantity, on its peak value phi = max|q|, over the three finest levels
of the reference's kind, the reference the finest; Roache 1998, Celik et al. 2008):

- monotone, three levels: GCI = Fs |(phi1 - phi2)/phi1| / (r21^p - 1) with the observed order p,
  Fs = 1.25 inside the asymptotic range (GCI_medium / (r21^p GCI_fine) within a factor 1.25 of 1)
  and Fs = 3 outside it; the L2 band likewise, Fs L2(level 2 vs 1) / (r21^p - 1);
- oscillating (not monotone): half the range of the three peaks over |phi1| (Stern et al. 2001,
  J. Fluids Eng. 123, 793), and for L2 the distance of level 2 from the reference;
- two levels: Fs = 3 with order 1 assumed; one level: unknown.

An error is *below the reference's uncertainty* when |peak error| <= GCI (peak) or L2 <= the L2
band: the reference cannot tell it from zero.

Filtered quantities (``config.filters``): a quantity with a filter is compared as its low-passed
series, the same filter run on every case's and the reference's own series (metrics.compared_series);
``filters`` in the result states, per quantity, the filter or null (raw samples).

Recommendation over the SPH ratios (the worst L2 over the quantities): the smallest tested ratio
that meets the tolerance ("met"); else the error model (the largest of the per-quantity models,
``models.WorstError``) solved for the tolerance, rounded up to a whole ratio, "predicted" up to 3x the largest tested ratio and "extrapolated" beyond; "not
reachable: floor e_inf" when the tolerance is at or below the model's floor; with its predicted
error and CPU cost (95 % prediction intervals) and, once its case has run, the measured ones.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Sequence

from . import derive, metrics, models
from .study import Plan, StudyConfig

KINEMATIC = ("displacement", "velocity", "acceleration", "coordinates")
EXTRAPOLATION_LIMIT = 3.0  # a ratio beyond this many times the largest tested is "extrapolated"
ASYMPTOTIC_BAND = 1.25
MAX_EXACT_CELLS = 1_000_000  # beyond, particle counts scale with the area instead of being derived


def driven_histories(deck_path: Path) -> dict[str, str]:
    """Histories whose every node has a prescribed velocity: {name: why}. Their kinematic
    quantities follow the drive, not the solution, so they are no default quantities."""
    import numpy as np

    from ..driver import DeckProblem, load_model

    try:
        loaded = load_model(str(deck_path))
    except DeckProblem:
        return {}
    model, deck = loaded.model, loaded.deck
    driven: set[int] = set()
    for bc in deck.boundaries:
        if bc.type == "prescribed_velocity" and any(v is not None for v in bc.velocity):
            driven.update(int(n) for n in np.atleast_1d(model.target_nodes(bc.part, bc.set)))
    out = {}
    if not driven or model.n_nodes == 0:
        return out
    for h in deck.output.histories:
        if h.point is not None:
            nodes = [int(np.argmin(np.linalg.norm(model.coordinates - np.asarray(h.point), axis=1)))]
        else:
            nodes = [int(n) for n in np.atleast_1d(model.target_nodes(h.part, h.set))]
        if nodes and all(n in driven for n in nodes):
            out[h.name] = "its nodes have a prescribed velocity (a driven quantity)"
    return out


def choose_quantities(config: StudyConfig, ref_dir: Path, deck_path: Path) -> tuple[list[str], dict[str, str]]:
    """The quantities compared, and the default ones left out (with why)."""
    if config.quantities:
        return list(config.quantities), {}
    driven = driven_histories(deck_path)
    every = metrics.default_quantities(ref_dir)
    left = {q: driven[q.partition(".")[0]] for q in every
            if q.partition(".")[0] in driven and q.partition(".")[2] in KINEMATIC}
    kept = [q for q in every if q not in left]
    return (kept or ["glstat.kinetic"]), left


def quantity_filters(config: StudyConfig, quantities: Sequence[str]) -> dict[str, dict | None]:
    """The filter of each compared quantity (None: raw samples): its own entry in ``config.filters``,
    else the ``*`` entry; an entry naming no compared quantity is a StudyError."""
    filters = dict(config.filters or {})
    unknown = sorted(set(filters) - set(quantities) - {"*"})
    if unknown and quantities:
        raise derive.StudyError(f"--filter: {', '.join(unknown)} is no compared quantity "
                                f"(compared: {', '.join(quantities)})")
    return {q: filters.get(q, filters.get("*")) for q in quantities}


def describe_filter(settings: dict | None) -> str:
    from ..output.filters import describe

    return "raw samples" if settings is None else describe(**settings)


def pick_reference(config: StudyConfig, cases) -> tuple[object | None, Path | None, str, list[dict]]:
    """(case or None, histories folder or None, label, failed finer levels [{case, message}])."""
    if config.reference in ("ale", "finest"):
        kind = "ale" if config.reference == "ale" else "sph"
        of_kind = sorted((c for c in cases if c.kind == kind and c.role == "study"), key=lambda c: c.size)
        failed = []
        for c in of_kind:
            if c.status.get("state") == "done":
                return c, c.histories, c.name, failed
            failed.append({"case": c.name, "message": c.status.get("message") or c.status.get("state")})
        return None, None, f"no finished {kind.upper()} case", failed
    path = Path(config.reference)
    for candidate in (path / "run" / "histories", path / "histories", path):
        if candidate.is_dir() and any(candidate.glob("*.csv")):
            return None, candidate, str(path), []
    raise derive.StudyError(f"--reference {path}: no history CSVs found there (give a run folder)")


def reference_uncertainty(levels: list[dict], quantities: Sequence[str]) -> dict:
    """Per quantity: {gci, extrapolated, l2, method, order, monotone, asymptotic} of the reference
    (``levels``: the finished rows of its kind, finest first, the reference first)."""
    out = {}
    for q in quantities:
        peaks = [r["errors"].get(q, {}).get("peak_value") for r in levels[:3]]
        n = 0
        while n < len(peaks) and peaks[n] is not None and math.isfinite(peaks[n]):
            n += 1
        l2_2 = levels[1]["errors"].get(q, {}).get("l2") if n >= 2 else None
        u = {"gci": None, "extrapolated": None, "l2": None, "method": "one level: unknown", "order": None,
             "monotone": None, "diverging": None, "asymptotic": None, "levels": [r["case"] for r in levels[:n]]}
        if n >= 3:
            conv = metrics.three_grid([r["size"] for r in levels[:3]], peaks)
            r21 = levels[1]["size"] / levels[0]["size"]
            u.update(order=conv.order, monotone=conv.monotone, diverging=conv.diverging, asymptotic=conv.asymptotic)
            if conv.monotone and math.isfinite(conv.order):
                inside = math.isfinite(conv.asymptotic) and 1 / ASYMPTOTIC_BAND <= conv.asymptotic <= ASYMPTOTIC_BAND
                fs = 1.25 if inside else 3.0
                u.update(gci=conv.gci_fine * fs / 1.25, extrapolated=conv.extrapolated,
                         l2=fs * l2_2 / (r21**conv.order - 1.0) if l2_2 is not None else None,
                         method=f"GCI, Fs {fs:g} ({'inside' if inside else 'outside'} the asymptotic range)")
            else:
                u.update(gci=0.5 * (max(peaks) - min(peaks)) / abs(peaks[0]) if peaks[0] else None, l2=l2_2,
                         method=("differences grow" if conv.diverging else "oscillating")
                         + ": half the range of the three levels")
        elif n == 2:
            r21 = levels[1]["size"] / levels[0]["size"]
            u.update(gci=3.0 * abs((peaks[1] - peaks[0]) / peaks[0]) / (r21 - 1.0) if peaks[0] else None,
                     l2=3.0 * l2_2 / (r21 - 1.0) if l2_2 is not None else None,
                     method="two levels: Fs 3, order 1 assumed")
        out[q] = u
    return out


def _worst(row: dict) -> float:
    vals = [e["l2"] for e in row["errors"].values() if isinstance(e.get("l2"), float) and math.isfinite(e["l2"])]
    return max(vals) if vals else float("nan")


def _count_at(data: dict, ratio: int, known: list[dict]) -> float:
    """SPH particles at ``ratio``: derived exactly, or scaled with the area from the finest tested case."""
    info = derive.ale_info(derive.validated(data))
    if info.n_elements * ratio**2 <= MAX_EXACT_CELLS:
        return float(sum(derive.sph_variant(data, ratio).parts.values()))
    ref = max(known, key=lambda r: r["ratio"])
    return ref["particles"] * (ratio / ref["ratio"]) ** 2


def cost_models(rows: list[dict]) -> dict:
    """Per kind: cpu_s = a + c N steps and peak_mib = m0 + m1 N over its finished study cases."""
    out = {}
    for kind in ("sph", "ale"):
        done = [r for r in rows if r["kind"] == kind and r["state"] == "done" and r["role"] == "study"
                and r.get("cpu_s") and r.get("steps")]
        cost = models.linear_fit([r["count"] * r["steps"] for r in done], [r["cpu_s"] for r in done])
        memory = models.linear_fit([r["count"] for r in done], [r["peak_mib"] for r in done])
        out[kind] = {
            "cost": {"form": "cpu_s = a + c * N * steps", "coefficients": {"a": cost.a, "c": cost.c} if cost else None,
                     "residual": cost.s if cost else None, "points": len(done), "fit": cost},
            "memory": {"form": "peak_mib = m0 + m1 * N",
                       "coefficients": {"m0": memory.a, "m1": memory.c} if memory else None,
                       "residual": memory.s if memory else None, "fit": memory},
        }
    return out


def _predict(data: dict, ratio: int, sph: list[dict], error_model, cost_fit, memory_fit) -> dict:
    ref = max(sph, key=lambda r: r["ratio"])
    particles = _count_at(data, ratio, sph)
    steps = models.steps_at(ref.get("dt0"), ref["steps"], ref["ratio"], ratio, "sph")
    err, err_iv = error_model.predict(ratio)
    cpu, cpu_iv = cost_fit.predict(particles * steps) if cost_fit else (None, None)
    mem, mem_iv = memory_fit.predict(particles) if memory_fit else (None, None)
    return {"error": err, "error_interval": err_iv, "cpu_s": cpu, "cpu_interval": cpu_iv, "particles": particles,
            "steps": steps, "peak_mib": mem, "peak_mib_interval": mem_iv}


def _pct(v) -> str:
    return "?" if v is None or not math.isfinite(v) else f"{100 * v:.3g} %"


def _brief(message, width: int = 240) -> str:
    """A failure message on one line, at most `width` characters: the recommendation's text is one
    line (report.md prints it in bold); the full message stays in ``failures`` and the Failures section."""
    line = " ".join(str(message).split())
    return line if len(line) <= width else line[: width - 3] + "..."


def recommend(config: StudyConfig, plan: Plan, rows: list[dict], error_model, costs: dict, ref_label: str,
              failures: list[dict]) -> dict:
    tol = config.tolerance
    sph = sorted((r for r in rows if r["kind"] == "sph" and r["state"] == "done" and r["role"] == "study"
                  and not r["reference"] and math.isfinite(r["worst_l2"])), key=lambda r: r["ratio"])
    rec = {"tolerance": tol, "ratio": None, "verdict": None, "predicted": None, "verified": None, "text": "",
           "failures": failures, "notes": []}
    if failures:
        rec["notes"].append("failed: " + "; ".join(f"{f['case']}: {_brief(f['message'])}" for f in failures))
    if not any(r["reference"] for r in rows) and ref_label.startswith("no finished"):
        rec["verdict"] = f"failed: {ref_label}, so no errors"
        rec["text"] = rec["verdict"] + "".join(f"; {n}" for n in rec["notes"])
        return rec
    if not sph:
        rec["verdict"] = "failed: no SPH case finished"
        rec["text"] = rec["verdict"] + "".join(f"; {n}" for n in rec["notes"])
        return rec
    largest = max(r["ratio"] for r in sph)
    cost_fit, memory_fit = costs["sph"]["cost"]["fit"], costs["sph"]["memory"]["fit"]
    met = next((r for r in sph if r["worst_l2"] <= tol), None)
    ale = next((r for r in rows if r["reference"] and r.get("cpu_s")), None)
    tail = f"; the reference {ale['case']} took {ale['cpu_s']:.3g} s CPU" if ale else ""
    if met is not None:
        rec.update(ratio=int(round(met["ratio"])), verdict="met")
        if error_model is not None:
            rec["predicted"] = _predict(plan.data, rec["ratio"], sph, error_model, cost_fit, memory_fit)
        rec["text"] = (f"use ratio {rec['ratio']}: worst L2 error {_pct(met['worst_l2'])} <= {_pct(tol)} against "
                       f"{ref_label} (tested), {met['count']} particles, {met['cpu_s']:.3g} s CPU{tail}")
    elif error_model is None:
        rec["verdict"] = "not reachable: one SPH ratio gives no error model"
        rec["text"] = f"no tested ratio reaches {_pct(tol)} (best {_pct(min(r['worst_l2'] for r in sph))}); " \
                      "run more ratios for a model"
    else:
        r_star, blocker = error_model.solve(tol)
        best = min(r["worst_l2"] for r in sph)
        if r_star is None:
            m = error_model.models[blocker]
            why = (f"floor e_inf = {_pct(m.floor)}" if error_model.falls(m)
                   else f"the error does not fall with the ratio (largest {_pct(max(m.e))})")
            rec["verdict"] = f"not reachable: {why} ({blocker})"
            rec["text"] = (f"no tested ratio reaches {_pct(tol)} against {ref_label} (best {_pct(best)}) and none will: "
                           f"{blocker}: {why} ({m.form} model): refining the particles alone never gets there{tail}")
        elif not math.isfinite(r_star) or r_star > 1e9:
            q = error_model.governing(r_star if math.isfinite(r_star) else 1e9)
            rec["verdict"] = f"extrapolated: ratio {r_star:.3g}, beyond any run"
            rec["text"] = (f"the {error_model.models[q].form} model of {q} needs ratio {r_star:.3g} for {_pct(tol)}: "
                           f"extrapolated{tail}")
        else:
            ratio = max(math.ceil(r_star - 1e-9), int(largest) + 1)
            rec["ratio"] = ratio
            rec["verdict"] = "predicted" if ratio <= EXTRAPOLATION_LIMIT * largest else "extrapolated"
            p = rec["predicted"] = _predict(plan.data, ratio, sph, error_model, cost_fit, memory_fit)
            q = error_model.governing(ratio)
            cost = f", about {p['cpu_s']:.3g} s CPU" if p["cpu_s"] is not None else ""
            rec["text"] = (f"{'use' if rec['verdict'] == 'predicted' else 'extrapolated:'} ratio {ratio} "
                           f"({q}'s {error_model.models[q].form} model, r = {r_star:.3g} rounded up; largest tested "
                           f"{largest:g}): worst L2 error {_pct(p['error'])}, {p['particles']:.3g} particles{cost}{tail}")
    if rec["predicted"] is None and error_model is not None and rec["ratio"] is not None:
        rec["predicted"] = _predict(plan.data, rec["ratio"], sph, error_model, cost_fit, memory_fit)
    rec["text"] += "".join(f"; {n}" for n in rec["notes"])
    return rec


def verification(rec: dict, rows: list[dict]) -> dict | None:
    """Measured against predicted error and cost of the recommended ratio, once its case has run."""
    if rec.get("ratio") is None or not rec.get("predicted"):
        return None
    row = next((r for r in rows if r["kind"] == "sph" and abs(r["ratio"] - rec["ratio"]) < 1e-6), None)
    if row is None:
        return None
    if row["state"] != "done":  # its failure is in the recommendation's failures
        return None
    measured = {"error": row["worst_l2"], "cpu_s": row.get("cpu_s"), "peak_mib": row.get("peak_mib"),
                "steps": row.get("steps"), "particles": row.get("particles")}
    pred = rec["predicted"]

    def rel(p, m):
        return (p - m) / m if p is not None and m else None

    return {"case": row["case"], "in_fit": row["role"] == "study", "measured": measured,
            "prediction_error": {k: rel(pred.get(k), measured[k]) for k in ("error", "cpu_s", "peak_mib", "steps")}}


def evaluate(config: StudyConfig, plan: Plan) -> dict:
    """Errors, convergence, models and recommendation, as one JSON-ready dict."""
    cases = plan.cases
    ref_case, ref_dir, ref_label, failed_refs = pick_reference(config, cases)
    quantities, left_out = (choose_quantities(config, ref_dir, Path(config.deck)) if ref_dir is not None
                            else (list(config.quantities or []), {}))
    filters = quantity_filters(config, quantities)
    ref_series = {}
    for q in quantities:
        try:
            ref_series[q] = metrics.compared_series(ref_dir, q, filters[q])
        except KeyError as err:
            raise derive.StudyError(f"--quantities: {err.args[0]}") from None
        except ValueError as err:
            raise derive.StudyError(f"--filter {q}: {err}") from None
    rows = []
    for c in cases:
        row = {"case": c.name, "name": c.name, "method": c.kind, "kind": c.kind, "size": c.size, "ratio": c.ratio,
               "count": c.count, "role": c.role, "reference": ref_case is c, "errors": {},
               **{k: c.status.get(k) for k in (
                   "state", "cpu_s", "cpu_spread", "cpu_runs", "compile_s", "warmup_cpu_s", "wall_s", "peak_mib",
                   "steps", "particles", "ale_elements", "solid_elements", "dt0", "message")}}
        if c.status.get("state") == "done" and ref_dir is not None:
            for q in quantities:
                try:
                    t, v = metrics.compared_series(c.histories, q, filters[q])
                except KeyError as err:
                    row["errors"][q] = {"missing": str(err)}
                    continue
                except ValueError as err:
                    raise derive.StudyError(f"--filter {q} on {c.name}: {err}") from None
                row["errors"][q] = metrics.history_error(t, v, *ref_series[q]).as_dict()
        row["worst_l2"] = _worst(row)
        rows.append(row)

    kind = ref_case.kind if ref_case is not None else None
    levels = sorted((r for r in rows if r["method"] == kind and r["state"] == "done" and r["role"] == "study"),
                    key=lambda r: r["size"])
    uncertainty = reference_uncertainty(levels, quantities) if kind else {}
    for r in rows:
        for q, e in r["errors"].items():
            u = uncertainty.get(q, {})
            if "l2" in e:
                e["below_reference_uncertainty"] = {
                    "l2": None if u.get("l2") is None else bool(e["l2"] <= u["l2"]),
                    "peak": None if u.get("gci") is None else bool(abs(e["peak"]) <= u["gci"])}

    convergence = {}
    for k in ("sph", "ale"):
        done = sorted((r for r in rows if r["kind"] == k and r["state"] == "done" and r["role"] == "study"),
                      key=lambda r: r["size"])
        if len(done) >= 3:
            convergence[k] = {}
            for q in quantities:
                phis = [r["errors"].get(q, {}).get("peak_value") for r in done[:3]]
                if all(p is not None and math.isfinite(p) for p in phis):
                    convergence[k][q] = dict(metrics.three_grid([r["size"] for r in done[:3]], phis).as_dict(),
                                             cases=[r["case"] for r in done[:3]])

    sph = [r for r in rows if r["kind"] == "sph" and r["state"] == "done" and r["role"] == "study"
           and not r["reference"] and math.isfinite(r["worst_l2"])]
    fits = {}
    for q in quantities:
        pts = [(r["ratio"], r["errors"].get(q, {}).get("l2")) for r in sph]
        m = models.fit_error([p[0] for p in pts if p[1] is not None], [p[1] for p in pts if p[1] is not None])
        if m is not None:
            fits[q] = m
    per_quantity = {q: {"form": m.form, "floor": m.floor, "order": m.order, "c": m.c, "residual": m.s,
                        "falls": models.WorstError.falls(m), "largest": max(m.e)} for q, m in fits.items()}
    error_model = models.WorstError(fits) if fits else None
    costs = cost_models(rows)
    failures = [{"case": r["case"], "message": r.get("message") or r["state"]} for r in rows
                if r["state"] not in ("done",)]
    rec = recommend(config, plan, rows, error_model, costs, ref_label, failures)
    rec["verified"] = verification(rec, rows)
    at = rec["ratio"] or max((r["ratio"] for r in sph), default=1.0)
    model = {
        "error": ({**error_model.summary(at), "at_ratio": at,
                   "quantity": "worst L2 over the quantities: the largest of the per-quantity models; form, "
                               "floor, order and c are those of the governing quantity at at_ratio"}
                  if error_model else {"form": None, "floor": None, "order": None,
                                       "reason": f"{len(sph)} finished SPH ratio(s): no fit"}),
        "error_per_quantity": per_quantity,
        "cost": {k: v for k, v in costs["sph"]["cost"].items() if k != "fit"},
        "memory": {k: v for k, v in costs["sph"]["memory"].items() if k != "fit"},
        "ale": {"cost": {k: v for k, v in costs["ale"]["cost"].items() if k != "fit"},
                "memory": {k: v for k, v in costs["ale"]["memory"].items() if k != "fit"}},
        "steps": "steps(r) = steps(r_ref) dt0(r_ref) / dt0(r), the fluid's first step proportional to its spacing",
    }
    return {
        "deck": str(Path(config.deck).resolve()), "tolerance": config.tolerance, "quantities": quantities,
        "filters": {q: None if f is None else {**f, "description": describe_filter(f)} for q, f in filters.items()},
        "quantities_left_out": left_out, "plan_notes": plan.notes,
        "units": plan.data.get("units") or {}, "dimension": plan.data.get("dimension", 2),
        "reference": {"case": ref_label if ref_case is not None or ref_dir is not None else None,
                      "label": ref_label, "method": kind,
                      "sizes": [r["size"] for r in levels] if kind else [],
                      "levels": [r["case"] for r in levels] if kind else [],
                      "failed": failed_refs, "uncertainty": uncertainty},
        "cases": rows, "convergence": convergence, "model": model, "recommendation": rec,
        "worst_l2": {r["case"]: r["worst_l2"] for r in rows},
    }
