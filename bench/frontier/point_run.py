# SPDX-License-Identifier: MIT
"""One (problem, point) of the frontier: its scene, its run (dld-run; resumable from the run's own
checkpoints) and its measurements, kept in <out>/<problem>/<point>/result.json.

Measurements (SPEC 7; issue 17):
  dilute  lateral shift per column over columns [first, last] of the cell's path, y and the step
          taken where the centroid crosses whole columns (interpolated between samples), the
          run's mode (shared/column_tracker.hpp) and its largest volume change;
  dense   suspension mobility u_x / u_x,empty at t p' = t_pprime (box-mean u_x of the coupled run
          against dld-fluid alone on the same lattice, both from rest, interpolated at that time)
          and the largest volume change of any cell.
  capsule the capsule in shear (tests/validation: Ramanujan & Pozrikidis 1998's benchmark): steady
          Taylor deformation D (mean over the last 30 % of the strain); the knobs map onto it as
          capsule_args() says. Cost: wall seconds per run (one core; no pillars).
Cost: steps per pillar (dilute: between the two crossings; dense: lambda / mean u_x) and the
coupled steps per second of the run (the membrane log's last progress line), so wall seconds per
pillar = steps per pillar / steps per second, on one core per run."""
import json
import math
import os
import re
import subprocess

import numpy as np

import scene_text
from grid import KNOB_DEFAULTS, KNOBS

os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")
import h5py  # noqa: E402


def scene_for(grid, problem, point, stem):
    """The point's scene: the template, the problem's case, the point's knobs, outputs in stem."""
    doc = scene_text.read(grid.template)
    v = problem.values
    scene_text.set_key(doc, "scene.name", f"{problem.name}-{point.name}")
    scene_text.set_key(doc, "scene.description", f"frontier {grid.title}: {problem.name}, "
                       f"point {point.name}")
    scene_text.set_key(doc, "geometry.row_shift_um", float(v["row_shift_um"]))
    scene_text.set_key(doc, "membrane.capillary_number", float(v["capillary_number"]))
    for knob, value in point.knobs.items():
        if KNOB_DEFAULTS.get(knob) != value:  # a default left out keeps older runs' scenes
            scene_text.set_key(doc, KNOBS[knob][0], value)
    scene_text.set_key(doc, "output.file", stem + ".h5")
    scene_text.set_key(doc, "output.fields", False)
    scene_text.set_key(doc, "run.threads", 1)
    scene_text.set_key(doc, "coupling.timeout_s", 300.0)
    if problem.kind in ("dense", "stability"):
        doc["cells"] = {"count": v["cells"], "seed": v.get("seed", 1)}
    return doc


def _tail_match(path, pattern):
    """The last match of pattern in a log file, or None."""
    last = None
    try:
        with open(path, errors="replace") as f:
            for line in f:
                m = re.search(pattern, line)
                if m:
                    last = m
    except OSError:
        return None
    return last


def _failure(stem):
    """'unstable at step N' or the first error line of a failed run, else None."""
    for log in (stem + "-cells-0.log", stem + "-fluid.log", stem + ".out"):
        m = _tail_match(log, r"unstable: .* at step (\d+)")
        if m:
            return f"unstable at step {m.group(1)}", m.group(0)
        m = _tail_match(log, r"fluid: velocity .* after step (\d+) \(limit.*")
        if m:
            return f"unstable at step {m.group(1)}", m.group(0).strip()
    for log in (stem + ".out", stem + "-fluid.log", stem + "-cells-0.log"):
        m = _tail_match(log, r"(error|Error|ERROR)[: ].*")
        if m:
            return "failed", m.group(0).strip()
    return None


def _dry_run(run_exe, scene):
    """p' [Pa/m] and dt [s] as the programs resolve them (conversions live in shared/units)."""
    r = subprocess.run([run_exe, scene, "--membrane", "cells", "--dry-run"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError((r.stderr or r.stdout).strip().splitlines()[-1])
    p = re.search(r"p' = ([0-9.e+-]+) Pa/m", r.stdout)
    dt = re.search(r"dt ([0-9.e+-]+) s", r.stdout)
    return float(p.group(1)), float(dt.group(1))


def _crossings(samples, lam):
    """(step, y) where the centroid crosses x0 + c lambda, c = 1, 2, ... (linear in between)."""
    step, x, y = samples[:, 0], samples[:, 1] - samples[0, 1], samples[:, 2]
    out, c = [], 1
    for i in range(1, len(x)):
        while x[i] >= c * lam > x[i - 1]:
            w = (c * lam - x[i - 1]) / (x[i] - x[i - 1])
            out.append((step[i - 1] + w * (step[i] - step[i - 1]), y[i - 1] + w * (y[i] - y[i - 1])))
            c += 1
    return out


def _steps_per_s(stem):
    """Coupled steps per second of the run's last segment without its start-up: from the membrane
    program's closing "time per step" line, else its last progress line."""
    m = _tail_match(stem + "-cells-0.log",
                    r"time per step \[ms\]: membrane ([0-9.]+), exchange and fluid ([0-9.]+)")
    if m:
        return 1e3 / (float(m.group(1)) + float(m.group(2)))
    m = _tail_match(stem + "-cells-0.log", r"([0-9.]+) steps/s")
    return float(m.group(1)) if m else math.nan


def _largest_volume_change(stem):
    worst = math.nan
    try:
        with open(stem + "-cells-0.log", errors="replace") as f:
            for line in f:
                m = re.search(r"summary: .*\(largest ([0-9.]+) %\)", line)
                if m:
                    worst = max(float(m.group(1)), 0 if math.isnan(worst) else worst)
    except OSError:
        pass
    return worst


def dilute_metrics(stem, columns):
    with h5py.File(stem + "-cells-0.h5", "r") as f:
        rows = f["cells/samples"][...]
        lam = float(f["cells"].attrs["pillar_spacing_um"])
        d = float(f["cells"].attrs["row_shift_um"])
    first, last = columns
    cross = _crossings(rows, lam)
    if len(cross) < last:
        return {"status": f"pending ({len(cross)} of {last} columns)"}
    (s1, y1), (s2, y2) = cross[first - 1], cross[last - 1]
    mode = _tail_match(stem + "-cells-0.log", r"summary: cell 0\s+mode (\w+)")
    if not mode:  # still running (a reference run longer than the problem): its mode so far
        mode = _tail_match(stem + "-cells-0.log", r"modes 0:(\w+\??)")
        mode_text = f"{mode.group(1)} (so far)" if mode else "?"
    else:
        mode_text = mode.group(1)
    steps_per_pillar = (s2 - s1) / (last - first)
    rate = _steps_per_s(stem)
    return {"status": "ok", "shift_per_column_um": (y2 - y1) / (last - first), "row_shift_um": d,
            "mode": mode_text, "steps_per_pillar": steps_per_pillar,
            "steps_per_s": rate, "wall_s_per_pillar": steps_per_pillar / rate,
            "volume_change_pct": _largest_volume_change(stem)}


def _ux_at(path, t):
    with h5py.File(path, "r") as f:  # a run file (dld-run) or a fluid part file (dld-fluid)
        ts = f["fluid/timeseries" if "fluid" in f else "timeseries"][...]
    if ts.shape[0] == 0 or ts[-1, 1] < t:
        return math.nan
    return float(np.interp(t, ts[:, 1], ts[:, 2]))


def dense_metrics(stem, empty, t_pprime, lam_um):
    with h5py.File(stem + ".h5", "r") as f:
        pprime = float(f["fluid/scene"].attrs["pressure_gradient_Pa_per_m"])
        dt = float(f["fluid/scene"].attrs["dt_s"])
    t = t_pprime / pprime
    ux, ux_empty = _ux_at(stem + ".h5", t), _ux_at(empty, t)
    if math.isnan(ux) or math.isnan(ux_empty):
        return {"status": "pending (t p' not reached)"}
    steps_per_pillar = lam_um * 1e-6 / (ux * dt)
    rate = _steps_per_s(stem)
    return {"status": "ok", "mobility": ux / ux_empty, "steps_per_pillar": steps_per_pillar,
            "steps_per_s": rate, "wall_s_per_pillar": steps_per_pillar / rate,
            "volume_change_pct": _largest_volume_change(stem)}


def _write_scene(path, doc):
    """Writes the scene; True if it changed (an earlier grid's run there is then discarded)."""
    new = scene_text.text(doc)
    try:
        with open(path) as f:
            if f.read() == new:
                return False
    except OSError:
        pass
    with open(path, "w") as f:
        f.write(new)
    return True


def _interrupted(returncode):
    """A run stopped by a signal (negative: killed by it; 130: dld-run's Ctrl-C exit), not one
    that failed: its result is not kept, so the next frontier command runs or resumes it."""
    return returncode < 0 or returncode == 130


# What a scene means when it does not name a knob (docs/scene-keys.md).
DEFAULTS = {"ib_kernel": "peskin4", "force_every": 1, "viscosity_field_every": 1, **KNOB_DEFAULTS}


def _external(problem, point, stem):
    """The reference point read from a run made elsewhere (scripts/dilute-map --fine): its scene
    must be the point's, knob for knob."""
    doc = scene_text.read(stem + ".toml")
    for knob, value in point.knobs.items():
        *tables, key = KNOBS[knob][0].split(".")
        t = doc
        for name in tables:
            t = t.get(name, {})
        have = t.get(key, DEFAULTS.get(knob))
        if have != value:
            raise RuntimeError(f"reference_run {stem}.toml: {KNOBS[knob][0]} = {have!r}, the "
                               f"reference point has {knob} = {value!r}")
    return dilute_metrics(stem, problem.values["columns"])


# The capsule problem at the reference lattice spacing: the validation's set-up (docs/validation.md:
# a = 6 nodes, box 8a x 8a x 10a, 1280 faces) at dx 0.4 um, i.e. a = 2.4 um.
CAPSULE_RADIUS_UM, CAPSULE_FACES_AT_2000 = 2.4, 1280


def capsule_args(problem, point):
    """dld-capsule-shear's options for a point: dx sets a = 2.4 um / dx nodes (box 8a x 8a x 10a),
    mesh_faces scales the icosphere (1280 faces at the DLD mesh's 2000; the nearest 20 * 4^n is
    used), reynolds is the capsule's Re = gammadot a^2 / nu (0.1 at the reference, as the
    validation), ib_kernel, force_every, spread_held, interpolation_held and collision as in a coupled run; viscosity_field_every does not
    apply (viscosity ratio 1, as the benchmark), nor volume_correction_every (the driver has no
    volume correction) nor wall_rule (a shear box has no pillar): a point that sets these
    measures the coupled problems only."""
    k = point.knobs
    a = CAPSULE_RADIUS_UM / k["dx_um"]
    return ["--ca", repr(float(problem.values["capillary_number"])), "--radius", f"{a:.6g}",
            "--nx", str(round(8 * a)), "--ny", str(round(8 * a)), "--nz", str(round(10 * a)),
            "--faces", str(round(CAPSULE_FACES_AT_2000 * k["mesh_faces"] / 2000)),
            "--re", repr(float(k["reynolds"])), "--ib-kernel", k["ib_kernel"],
            "--force-every", str(k["force_every"]), "--strain", repr(float(problem.values["strain"])),
            "--sample-every", "20", "--transport", "inproc"] + (
                [] if k["collision"] == KNOB_DEFAULTS["collision"] else ["--collision", k["collision"]]) + (
                ["--spread-held"] if k["spread_held"] else []) + (
                ["--interpolation-held"] if k["interpolation_held"] else [])


def run_capsule(problem, point, d, exe):
    """One capsule run (or its kept result when the options are unchanged)."""
    args = capsule_args(problem, point)
    args_file, result_file = os.path.join(d, "args.txt"), os.path.join(d, "result.json")
    same = os.path.exists(args_file) and open(args_file).read() == " ".join(args) + "\n"
    if same and os.path.exists(result_file):
        with open(result_file) as f:
            return json.load(f)
    with open(args_file, "w") as f:
        f.write(" ".join(args) + "\n")
    out = os.path.join(d, "run.out")
    with open(out, "w") as log:
        r = subprocess.run([exe["capsule"], *args, "--csv", os.path.join(d, "run.csv")],
                           stdout=log, stderr=subprocess.STDOUT, env={**os.environ,
                                                                    "OMP_NUM_THREADS": "1"})
    text = open(out, errors="replace").read()
    if _interrupted(r.returncode):  # a stop (long-runs stop, Ctrl-C) is no result: run it again
        return {"status": "interrupted (resumable)"}
    if r.returncode != 0:
        why = (text.strip().splitlines() or [f"exit code {r.returncode}"])[-1]
        return _keep(result_file, {"status": "failed", "why": why})
    steady = re.search(r"steady D \(mean over gammadot t >= [0-9.]+\) = ([0-9.]+)", text)
    cost = re.search(r"steps (\d+) wall ([0-9.]+) s .*volume change ([-0-9.e+]+)", text)
    if not steady or not cost:
        return _keep(result_file, {"status": "failed", "why": "no steady D in " + out})
    res = {"status": "ok", "D": float(steady.group(1)), "steps": int(cost.group(1)),
           "wall_s": float(cost.group(2)), "volume_change_pct": 100 * abs(float(cost.group(3)))}
    res["steps_per_s"] = res["steps"] / res["wall_s"] if res["wall_s"] > 0 else math.nan
    lit = problem.values.get("literature_D")
    if lit:
        res["literature_error"] = (res["D"] - lit) / lit
    return _keep(result_file, res)


def run(grid, problem, point, out, exe):
    """Runs (or resumes, or reads) one point and returns its result (also kept as result.json)."""
    d = os.path.join(out, problem.name, point.name)
    os.makedirs(d, exist_ok=True)
    if problem.kind == "capsule":
        return run_capsule(problem, point, d, exe)
    stem, result_file = os.path.join(d, "run"), os.path.join(d, "result.json")
    if point.name == "reference" and "reference_run" in problem.values:
        return _external(problem, point, problem.values["reference_run"])
    scene = os.path.join(d, "scene.toml")
    doc = scene_for(grid, problem, point, stem)
    try:
        if problem.kind == "dense":  # the steps to t p' (and the sampling) from the programs' p', dt
            probe = scene + ".probe"
            with open(probe, "w") as f:
                f.write(scene_text.text(doc))
            try:
                pprime, dt = _dry_run(exe["run"], probe)
            finally:
                os.remove(probe)
            steps = math.ceil(1.02 * problem.values["t_pprime_Pa_s_per_m"] / pprime / dt) + 10
            scene_text.set_key(doc, "run.log_every", max(10, steps // 100))
            args = ["--steps", str(steps)]
        elif problem.kind == "stability":
            args = ["--steps", str(problem.values["steps"])]
        else:
            args = ["--steps", "1000000000000", "--pillars", str(problem.values["columns"][1])]
    except RuntimeError as e:
        _write_scene(scene, doc)
        why = str(e).replace(scene + ".probe", scene)  # the probe is the scene, written early
        return _keep(result_file, {"status": "refused", "why": why})
    changed = _write_scene(scene, doc)
    if not changed and os.path.exists(result_file):
        with open(result_file) as f:
            return json.load(f)
    if changed:  # an earlier grid's run of this point is not resumed under the new scene
        for name in os.listdir(d):
            if name != "scene.toml":
                os.remove(os.path.join(d, name))
    args += ["--checkpoint-every", "20000"]  # a few minutes of one core: little lost at a stop
    if os.path.exists(stem + "-fluid.ckpt.h5"):
        args.append("--resume")
    with open(stem + ".out", "a") as log:
        r = subprocess.run([exe["run"], scene, "--membrane", "cells", *args], stdout=log,
                           stderr=subprocess.STDOUT)
    if _interrupted(r.returncode):
        return {"status": "interrupted (resumable)"}
    if r.returncode != 0:
        f = _failure(stem) or ("failed", f"dld-run exit code {r.returncode}")
        return _keep(result_file, {"status": f[0], "why": f[1]})
    if problem.kind == "stability":
        res = {"status": "ok", "why": f"ran {problem.values['steps']} steps",
               "steps_per_s": _steps_per_s(stem),
               "volume_change_pct": _largest_volume_change(stem)}
    elif problem.kind == "dense":
        empty = os.path.join(d, "empty.h5")
        with open(os.path.join(d, "empty.out"), "w") as log:
            e = subprocess.run([exe["fluid"], scene, "--steps", args[1], "--threads", "1",
                                "-o", empty], stdout=log, stderr=subprocess.STDOUT)
        if _interrupted(e.returncode):
            return {"status": "interrupted (resumable)"}
        if e.returncode != 0:
            return _keep(result_file, {"status": "failed", "why": "empty-device run failed"})
        res = dense_metrics(stem, empty, problem.values["t_pprime_Pa_s_per_m"],
                            float(doc["geometry"]["pillar_spacing_um"]))
    else:
        res = dilute_metrics(stem, problem.values["columns"])
    return _keep(result_file, res) if res["status"] == "ok" else res


def _keep(path, result):
    with open(path, "w") as f:
        json.dump(result, f, indent=1)
    return result


def ran_here(problem, point, out):
    """Whether this machine holds the point's own result (a record row then gives way to it)."""
    if point.name == "reference" and "reference_run" in problem.values:
        return os.path.exists(problem.values["reference_run"] + "-cells-0.h5")
    return os.path.exists(os.path.join(out, problem.name, point.name, "result.json"))


def read_only(problem, point, out):
    """What is known of a point without running anything (--report-only)."""
    if point.name == "reference" and "reference_run" in problem.values:
        return _external(problem, point, problem.values["reference_run"])
    path = os.path.join(out, problem.name, point.name, "result.json")
    if not os.path.exists(path):
        return {"status": "not run"}
    with open(path) as f:
        return json.load(f)
