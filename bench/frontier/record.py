# SPDX-License-Identifier: MIT
"""The frontier's record (issue 17): the finished points' results, kept as a small CSV beside the
report's figures and committed with them. Run folders do not move with the project (a new machine
starts with an empty runs/), so without it a grid's report would lose every row it had and its
points would run again. A record row stands for a point only while the point's knobs and its
problem's values are the ones it was run with; a point run on this machine (its result.json) is
preferred to its record row.

Columns: problem, point, knobs and values (JSON, the match), source (when and where the result was
made), then one column per result field (status, why, the metrics, the costs)."""
import csv
import json
import math
import os

from grid import KNOB_DEFAULTS

KEY_COLUMNS = ["problem", "point", "knobs", "values", "source"]
KEPT = ("ok", "unstable", "failed", "refused")  # results a run keeps (not pending/interrupted)


def _match(problem, point):
    return (json.dumps(point.knobs, sort_keys=True), json.dumps(problem.values, sort_keys=True))


def _value(text):
    """A CSV cell back as the number it was written from, else as text."""
    try:
        v = float(text)
    except ValueError:
        return text
    return int(v) if text.lstrip("-").isdigit() else v


def read(path):
    """(problem, point) -> (knobs, values, source, result) of the record; {} when there is none.
    A malformed record is an error naming the file."""
    if not os.path.exists(path):
        return {}
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    kept = {}
    for n, row in enumerate(rows, 2):
        if any(row.get(k) is None for k in KEY_COLUMNS):
            raise ValueError(f"{path}: line {n}: expected the columns {', '.join(KEY_COLUMNS)}")
        result = {k: _value(v) for k, v in row.items() if k not in KEY_COLUMNS and v != ""}
        if "status" not in result:
            raise ValueError(f"{path}: line {n}: no status")
        kept[(row["problem"], row["point"])] = (row["knobs"], row["values"], row["source"], result)
    return kept


def _recorded_knobs(text):
    """A row's knobs with the defaults of knobs added since it was written: the row stands for the
    point it was run as (a knob new to the grid had its default value then)."""
    return {**KNOB_DEFAULTS, **json.loads(text)}


def lookup(kept, problem, point):
    """The recorded result of this point, if it was made with its present knobs and problem."""
    entry = kept.get((problem.name, point.name))
    if entry is None or entry[1] != _match(problem, point)[1] \
            or _recorded_knobs(entry[0]) != point.knobs:
        return None
    return {**entry[3], "restored": entry[2]}


def _same(a, b):
    keys = (set(a) | set(b)) - {"restored"}
    return all(a.get(k) == b.get(k) or (isinstance(a.get(k), float) and isinstance(b.get(k), float)
                                        and math.isclose(a[k], b[k], rel_tol=1e-9)) for k in keys)


def write(path, grid, results, kept, source):
    """Records every kept result of the grid (restored ones with their source, new ones with
    `source`); rows of points the grid no longer has stay as they were."""
    rows = {}
    for key, (knobs, values, src, result) in kept.items():
        rows[key] = {"problem": key[0], "point": key[1], "knobs": knobs, "values": values,
                     "source": src, **result}
    for prob in grid.problems:
        for p in grid.points:
            r = results.get((prob.name, p.name), {})
            if not str(r.get("status", "")).startswith(KEPT):
                continue
            knobs, values = _match(prob, p)
            old = kept.get((prob.name, p.name))
            src = r.get("restored") or (old[2] if old and (old[0], old[1]) == (knobs, values)
                                        and _same(old[3], r) else source)
            rows[(prob.name, p.name)] = {"problem": prob.name, "point": p.name, "knobs": knobs,
                                         "values": values, "source": src,
                                         **{k: v for k, v in r.items() if k != "restored"}}
    fields = KEY_COLUMNS + sorted({k for r in rows.values() for k in r} - set(KEY_COLUMNS))
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, lineterminator="\n")
        w.writeheader()
        for key in sorted(rows):
            w.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in rows[key].items()})
