# SPDX-License-Identifier: MIT
"""The frontier's report: per problem a table (setting, metric, error against the reference point,
cost) and a log-log plot of error against wall seconds per pillar with the Pareto front drawn;
then the settings that meet the study's tolerances and the cheapest of them (`fast`).

Errors: dilute |s - s_ref| / d (the shift per column as a fraction of the row shift, the scale of
the two modes: ~d displacement, ~0 zigzag) and whether the mode is the reference's; dense
|M - M_ref| / M_ref of the mobility."""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402

TOLERANCE = {"dilute": 0.03, "dense": 0.05, "stability": 0.0, "capsule": 0.05}  # issue 17: `fast` is within these of the reference
FLOOR = 1e-4  # where a zero error is drawn on the log axis


GUIDE = """\
Each point changes numerics only (lattice spacing, mesh, Reynolds number, kernel, collision operator, update
intervals); the cell is the same at every point (C = 350.3 Ca, kappa_V, contact range relative
to r: `StudyCell` test). Errors are against the grid's reference point, which is itself only as
converged as the table shows (compare it with the point that refines it, e.g. Re 0.05):
- dilute: |s - s_ref| / d, s the lateral shift per column over the stated columns (after the
  entry transient), and whether the mode is the reference's;
- dense: |M - M_ref| / M_ref, M = u_x / u_x,empty at the stated t p' (both flows from rest);
- capsule: |D - D_ref| / D_ref, D the steady Taylor deformation of a capsule in shear (the
  validation's benchmark, a = 2.4 um: 6 nodes at dx 0.4 um), and its error against the
  literature; cost: wall seconds per run. It shows what a setting does to one membrane's
  deformation; `fast` is chosen on the dilute and dense problems only;
- cost: steps per pillar (deterministic) and wall seconds per pillar on one core (steps per
  pillar / coupled steps per second of the run; noisy on a shared machine: compare steps per
  pillar first). For a dense problem a pillar is lambda over the box-mean u_x at t p' (the
  suspension's speed at that time, not a settled run's): a cost per unit of physical time.

How to pick a setting for a new question: take the cheapest point whose errors on the problem
closest to yours (one cell: dilute; a suspension: dense) are within what the question can
afford, with the reference's mode; a question about a mode boundary (a case near the critical
diameter) needs the dilute error well below the margin to the boundary. If no point is close
enough, run the grid with your case as a problem (a [[problem]] table; `bench/frontier/frontier
--grid FILE` resumes what was run).""".splitlines()


def error(problem, res, ref):
    if problem.kind == "stability" or res.get("status") != "ok" or ref.get("status") != "ok":
        return math.nan
    if problem.kind == "dilute":
        return abs(res["shift_per_column_um"] - ref["shift_per_column_um"]) / res["row_shift_um"]
    if problem.kind == "capsule":
        return abs(res["D"] - ref["D"]) / ref["D"]
    return abs(res["mobility"] - ref["mobility"]) / ref["mobility"]


def _fmt(v, spec):
    return "-" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, spec)


def _knobs(point):
    def text(v):  # as the grid file writes it
        return str(v).lower() if isinstance(v, bool) else v
    return ", ".join(f"{k} {text(v)}" for k, v in point.changed.items()) or "(reference)"


def pareto(rows):
    """Names of the points no other point beats in both cost and error."""
    ok = [(c, e, n) for n, c, e in rows if not (math.isnan(c) or math.isnan(e))]
    return {n for c, e, n in ok
            if not any(c2 <= c and e2 <= e and (c2 < c or e2 < e) for c2, e2, _ in ok)}


def plot(problem, rows, path):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    front = pareto(rows)
    for name, cost, err in rows:
        if math.isnan(cost) or math.isnan(err):
            continue
        e = max(err, FLOOR)
        ax.loglog(cost, e, "o", color="C3" if name in front else "C0")
        ax.annotate(name + (" (0)" if err == 0 else ""), (cost, e), textcoords="offset points",
                    xytext=(4, 4), fontsize=8)
    f = sorted((c, max(e, FLOOR)) for n, c, e in rows if n in front)
    if f:
        ax.plot([c for c, _ in f], [e for _, e in f], "-", color="C3", lw=1, label="Pareto front")
    ax.axhline(TOLERANCE[problem.kind], ls=":", color="grey",
               label=f"tolerance {TOLERANCE[problem.kind]:.0%}")
    capsule = problem.kind == "capsule"
    ax.set_xlabel(f"wall time per {'run' if capsule else 'pillar'} [s] (one core)")
    ax.set_ylabel({"dilute": "|s - s_ref| / d", "capsule": "|D - D_ref| / D_ref"}.get(
        problem.kind, "|M - M_ref| / M_ref"))
    ax.set_title(f"{problem.name}: error against cost (zero drawn at {FLOOR:g})", fontsize=10)
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _case(problem):
    v = problem.values
    if problem.kind == "dilute":
        return f", columns {v['columns'][0]}-{v['columns'][1]})"
    if problem.kind == "dense":
        return f", {v['cells']} cells, t p' = {v['t_pprime_Pa_s_per_m']} Pa s/m)"
    if problem.kind == "capsule":
        lit = (f"; literature D {v['literature_D']}" + (f" ({v['literature']})" if "literature" in v
                                                        else "")) if "literature_D" in v else ""
        return f", gammadot t = {v['strain']}{lit})"
    return f", {v['cells']} cells, {v['steps']} steps)"


def envelope(problem, grid, results):
    """Per dx, the largest Re whose run of the stability problem went through, and the first
    failure above it (issue 17: the stability envelope)."""
    by_dx = {}
    for p in grid.points:
        r = results[(problem.name, p.name)]
        by_dx.setdefault(p.knobs["dx_um"], []).append((p.knobs["reynolds"], r, p.name))
    lines = ["| dx [um] | largest stable Re | first unstable (Re: what stopped it) |",
             "|---:|---:|---|"]
    for dx in sorted(by_dx):
        runs = sorted(by_dx[dx], key=lambda t: t[0])
        stable = [re for re, r, _ in runs if r.get("status") == "ok"]
        bad = [(re, r) for re, r, _ in runs if r.get("status", "").startswith("unstable")]
        first = (f"{bad[0][0]}: {bad[0][1]['status']} ({bad[0][1].get('why', '')})" if bad
                 else "none in the grid")
        lines.append(f"| {dx:.4g} | {max(stable) if stable else '-'} | {first} |")
    return lines


def _rows(problem, grid, results, columns, cost_key):
    """The table rows (one per point: setting, knobs, status, then `columns`, each a (header,
    align, value of (result, error)) triple) and the (name, cost, error) of each point."""
    ref = results[(problem.name, "reference")]
    lines = ["| setting | knobs | status | " + " | ".join(c[0] for c in columns) + " |",
             "|---|---|---|" + "|".join(c[1] for c in columns) + "|"]
    rows = []
    for p in grid.points:
        r = results[(problem.name, p.name)]
        err = error(problem, r, ref)
        status = r.get("status", "?") + (f": {r['why']}" if "why" in r else "")
        lines.append(f"| {p.name} | {_knobs(p)} | {status} | "
                     + " | ".join(c[2](r, err) for c in columns) + " |")
        rows.append((p.name, r.get(cost_key, math.nan), err))
    return lines, rows


def _literature(r, _):
    lit = r.get("literature_error")
    return "-" if lit is None else format(lit, "+.1%")


CAPSULE_COLUMNS = [
    ("D", "---:", lambda r, e: _fmt(r.get("D"), ".4f")),
    ("error", "---:", lambda r, e: _fmt(e, ".3g")),
    ("against the literature", "---:", _literature),
    ("largest dV [%]", "---:", lambda r, e: _fmt(r.get("volume_change_pct"), ".3f")),
    ("steps", "---:", lambda r, e: _fmt(r.get("steps"), "d")),
    ("steps/s", "---:", lambda r, e: _fmt(r.get("steps_per_s"), ".1f")),
    ("wall s", "---:", lambda r, e: _fmt(r.get("wall_s"), ".1f"))]


def _pillar_columns(kind):
    key = "shift_per_column_um" if kind == "dilute" else "mobility"
    return [
        ("shift/col [um]" if kind == "dilute" else "mobility", "---:",
         lambda r, e: _fmt(r.get(key), ".4f")),
        ("error", "---:", lambda r, e: _fmt(e, ".3g")),
        ("mode", "---", lambda r, e: str(r.get("mode", "-"))),
        ("largest dV [%]", "---:", lambda r, e: _fmt(r.get("volume_change_pct"), ".3f")),
        ("steps/pillar", "---:", lambda r, e: _fmt(r.get("steps_per_pillar"), ".0f")),
        ("steps/s", "---:", lambda r, e: _fmt(r.get("steps_per_s"), ".1f")),
        ("wall s/pillar", "---:", lambda r, e: _fmt(r.get("wall_s_per_pillar"), ".1f"))]


def _problem_table(problem, grid, results):
    v = problem.values
    if problem.kind == "capsule":
        head = f"### {problem.name} (capsule in shear: Ca {v['capillary_number']}" + _case(problem)
        table, rows = _rows(problem, grid, results, CAPSULE_COLUMNS, "wall_s")
    else:
        head = (f"### {problem.name} ({problem.kind}: d {v['row_shift_um']} um, "
                f"Ca {v['capillary_number']}" + _case(problem))
        table, rows = _rows(problem, grid, results, _pillar_columns(problem.kind),
                            "wall_s_per_pillar")
    return [head, ""] + table, rows


def mode_word(result):
    """The mode without a running reference's " (so far)"."""
    return str(result.get("mode", "?")).split(" ")[0]


def choose(grid, results):
    """(name, cost) of the cheapest point within every tolerance, modes as the reference's; the
    cost is the dense problem's wall time per pillar if there is one (the study's runs are dense),
    else the sum over the problems."""
    best = None
    dense = [p for p in grid.problems if p.kind == "dense"]
    for p in grid.points:
        ok, cost = True, 0.0
        for prob in grid.problems:
            if prob.kind in ("stability", "capsule"):
                continue
            r, ref = results[(prob.name, p.name)], results[(prob.name, "reference")]
            e = error(prob, r, ref)
            ok &= not math.isnan(e) and e <= TOLERANCE[prob.kind]
            if prob.kind == "dilute":
                ok &= mode_word(r) == mode_word(ref) != "?"
            if not dense or prob in dense:
                cost += r.get("wall_s_per_pillar", math.nan)
        if ok and not math.isnan(cost) and (best is None or cost < best[1]):
            best = (p.name, cost)
    return best


def wall_for_wall(grid, results):
    """Table lines: each point whose pillar wall rule is not the reference's, against the point
    that is the reference but for that wall (where the grid has it and it ran). The main tables
    hold the wall's own error at the finest point in every such point's error; this one tells the
    setting's other numerics apart from it."""
    ref = grid.reference.knobs
    lines = []
    for prob in grid.problems:
        if prob.kind == "stability":
            continue
        for wall_ref in (p for p in grid.points
                         if p.knobs["wall_rule"] != ref["wall_rule"]
                         and p.knobs == {**ref, "wall_rule": p.knobs["wall_rule"]}):
            base = results[(prob.name, wall_ref.name)]
            for p in grid.points:
                if p is wall_ref or p.knobs["wall_rule"] != wall_ref.knobs["wall_rule"]:
                    continue
                r = results[(prob.name, p.name)]
                e = error(prob, r, base)
                if math.isnan(e):
                    continue
                same = prob.kind != "dilute" or mode_word(r) == mode_word(base)
                within = e <= TOLERANCE[prob.kind] and same
                lines.append(f"| {prob.name} | {p.name} | {wall_ref.name} | {e:.3g} | "
                             f"{mode_word(r) if prob.kind == 'dilute' else '-'} | "
                             f"{'yes' if within else 'no'} |")
    if not lines:
        return []
    return ["## Wall for wall", "",
            "Points with another pillar wall rule than the reference's, against the reference with "
            "that wall (same metrics and tolerances as above):", "",
            "| problem | setting | against | error | mode | within tolerance |",
            "|---|---|---|---:|---|---|", *lines, ""]


def write(grid, results, doc_path, fig_dir, header):
    os.makedirs(fig_dir, exist_ok=True)
    lines = [f"# Speed against error: {grid.title}", "", *header, "", *GUIDE, ""]
    for prob in grid.problems:
        table, rows = _problem_table(prob, grid, results)
        if prob.kind == "stability":
            lines += table + ["", "Stability envelope:", ""] + envelope(prob, grid, results) + [""]
            continue
        png = os.path.join(fig_dir, f"frontier-{prob.name}.png")
        plot(prob, rows, png)
        lines += table + ["", f"![{prob.name}]({os.path.relpath(png, os.path.dirname(doc_path))})",
                          "", "Pareto front: " + ", ".join(sorted(pareto(rows))), ""]
    if not any(p.kind in ("dilute", "dense") for p in grid.problems):
        with open(doc_path, "w") as f:
            f.write("\n".join(lines) + "\n")
        return None
    best = choose(grid, results)
    lines += wall_for_wall(grid, results)
    lines += ["## The cheapest setting within tolerance", "",
              f"Tolerances: dilute shift within {TOLERANCE['dilute']:.0%} of d and the same mode; "
              f"dense mobility within {TOLERANCE['dense']:.0%} of the reference.", ""]
    if best:
        p = next(p for p in grid.points if p.name == best[0])
        lines.append(f"**{best[0]}** ({_knobs(p)}): {best[1]:.1f} wall s per pillar.")
    else:
        lines.append("No point meets every tolerance yet (or a point is pending).")
    with open(doc_path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return best
