# SPDX-License-Identifier: MIT
"""The frontier's grid file (configs/frontier/*.toml): the reference setting (the finest point),
the reference problems and the points, each point naming only the knobs it changes. Every error
is one line naming the file, the table and the key (GridError)."""
import tomllib
from dataclasses import dataclass, field

# knob -> (scene key, check, what is expected). Each changes numerics only: the cell's physics is
# fixed by the template at every setting (SPEC 9; tests/launcher/study_cell_test.cpp).
KNOBS = {
    "dx_um": ("lattice.dx_um", lambda v: _num(v) and 0.1 <= v <= 1.6,
              "a lattice spacing 0.1..1.6 um that divides 32 and 4.8 um"),
    "mesh_faces": ("membrane.mesh_faces", lambda v: _int(v) and 100 <= v <= 20000,
                   "a face count 100..20000"),
    "reynolds": ("drive.reynolds", lambda v: _num(v) and 0.005 <= v <= 5.0, "a Reynolds number 0.005..5"),
    "ib_kernel": ("coupling.ib_kernel", lambda v: v in ("peskin2", "peskin3", "peskin4"),
                  '"peskin2", "peskin3" or "peskin4"'),
    "force_every": ("coupling.force_every", lambda v: _int(v) and 1 <= v <= 1000, "steps 1..1000"),
    "viscosity_field_every": ("coupling.viscosity_field_every",
                              lambda v: _int(v) and 1 <= v <= 1000, "steps 1..1000"),
    "collision": ("lattice.collision", lambda v: v in ("trt", "bgk", "mrt"),
                  '"trt", "bgk" or "mrt"'),
    "spread_held": ("coupling.spread_held", lambda v: isinstance(v, bool), "true or false"),
    "interpolation_held": ("coupling.interpolation_held", lambda v: isinstance(v, bool),
                           "true or false (true needs spread_held = true)"),
    "wall_rule": ("lattice.wall_rule", lambda v: v in ("bounce_back", "bouzidi"),
                  '"bounce_back" or "bouzidi"'),
    "volume_correction_every": ("coupling.volume_correction_every",
                                lambda v: _int(v) and 0 <= v <= 1000000,
                                "steps 0..1000000 (0: never; a multiple of force_every)"),
}
# Knobs a grid may leave out of [reference]: their value where no point names them (a grid made
# before the knob existed keeps its runs: scenes name such a knob only where a point changes it).
KNOB_DEFAULTS = {"collision": "trt", "spread_held": False, "interpolation_held": False,
                 "volume_correction_every": 0, "wall_rule": "bounce_back"}
KINDS = {"dilute": ("row_shift_um", "capillary_number", "columns"),
         "dense": ("row_shift_um", "capillary_number", "cells", "t_pprime_Pa_s_per_m"),
         "stability": ("row_shift_um", "capillary_number", "cells", "steps"),
         "capsule": ("capillary_number", "strain")}
OPTIONAL = {"dilute": ("reference_run",), "dense": ("seed",), "stability": ("seed",),
            "capsule": ("literature_D", "literature")}


def _num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _int(v):
    return isinstance(v, int) and not isinstance(v, bool)


class GridError(Exception):
    pass


@dataclass
class Problem:
    name: str
    kind: str
    values: dict


@dataclass
class Point:
    name: str
    knobs: dict  # every knob, the reference's where the point does not change it
    changed: dict = field(default_factory=dict)


@dataclass
class Grid:
    path: str
    title: str
    template: str
    problems: list
    points: list  # the reference first

    @property
    def reference(self):
        return self.points[0]


def _check_knobs(path, where, table, require_all):
    for k, v in table.items():
        if k == "name":
            continue
        if k not in KNOBS:
            raise GridError(f"{path}: {where}: unknown knob '{k}' (expected one of "
                            f"{', '.join(KNOBS)})")
        if not KNOBS[k][1](v):
            raise GridError(f"{path}: {where}: '{k}' = {v!r}: expected {KNOBS[k][2]}")
    if require_all:
        missing = [k for k in KNOBS if k not in table and k not in KNOB_DEFAULTS]
        if missing:
            raise GridError(f"{path}: {where}: missing knob(s) {', '.join(missing)} "
                            "(the reference names every knob)")


def _problem(path, i, t):
    where = f"[[problem]] {i + 1}"
    name, kind = t.get("name"), t.get("kind")
    if not isinstance(name, str) or not name.replace("-", "").replace(".", "").isalnum():
        raise GridError(f"{path}: {where}: 'name' must be a word of letters, digits, '-' or '.'")
    if kind not in KINDS:
        raise GridError(f"{path}: {where} ({name}): 'kind' = {kind!r}: expected one of "
                        f"{', '.join(KINDS)}")
    allowed = {"name", "kind", *KINDS[kind], *OPTIONAL[kind]}
    for k in t:
        if k not in allowed:
            raise GridError(f"{path}: {where} ({name}): unknown key '{k}' for a {kind} problem "
                            f"(expected {', '.join(sorted(allowed))})")
    for k in KINDS[kind]:
        if k not in t:
            raise GridError(f"{path}: {where} ({name}): missing '{k}'")
    if kind == "dilute":
        c = t["columns"]
        if not (isinstance(c, list) and len(c) == 2 and all(_int(x) for x in c)
                and 1 <= c[0] < c[1] <= 200):
            raise GridError(f"{path}: {where} ({name}): 'columns' = {c!r}: expected [first, last] "
                            "whole columns, 1 <= first < last <= 200")
    elif kind == "capsule":
        if not (_num(t["capillary_number"]) and 0 < t["capillary_number"] <= 10):
            raise GridError(f"{path}: {where} ({name}): 'capillary_number' must be in (0, 10]")
        if not (_num(t["strain"]) and 0 < t["strain"] <= 100):
            raise GridError(f"{path}: {where} ({name}): 'strain' (gammadot t) must be in (0, 100]")
    else:
        if kind == "stability" and not (_int(t["steps"]) and 1 <= t["steps"] <= 10**9):
            raise GridError(f"{path}: {where} ({name}): 'steps' = {t['steps']!r}: expected 1..10^9")
        if not (_int(t["cells"]) and 1 <= t["cells"] <= 40):
            raise GridError(f"{path}: {where} ({name}): 'cells' = {t['cells']!r}: expected 1..40")
        if kind == "dense" and not (_num(t["t_pprime_Pa_s_per_m"]) and t["t_pprime_Pa_s_per_m"] > 0):
            raise GridError(f"{path}: {where} ({name}): 't_pprime_Pa_s_per_m' must be > 0")
    return Problem(name, kind, {k: v for k, v in t.items() if k not in ("name", "kind")})


def load(path):
    try:
        with open(path, "rb") as f:
            doc = tomllib.load(f)
    except OSError as e:
        raise GridError(f"{path}: cannot read the grid file ({e.strerror})") from None
    except tomllib.TOMLDecodeError as e:
        raise GridError(f"{path}: not TOML: {e}") from None
    for k in doc:
        if k not in ("frontier", "reference", "problem", "point"):
            raise GridError(f"{path}: unknown table [{k}] (expected [frontier], [reference], "
                            "[[problem]], [[point]])")
    head = doc.get("frontier", {})
    for k in head:
        if k not in ("title", "template"):
            raise GridError(f"{path}: [frontier]: unknown key '{k}' (expected title, template)")
    ref = doc.get("reference")
    if not isinstance(ref, dict):
        raise GridError(f"{path}: missing [reference] (the finest point's knobs)")
    _check_knobs(path, "[reference]", ref, require_all=True)
    problems = [_problem(path, i, t) for i, t in enumerate(doc.get("problem", []))]
    if not problems:
        raise GridError(f"{path}: no [[problem]]")
    ref = {**KNOB_DEFAULTS, **ref}
    points = [Point("reference", dict(ref))]
    for i, t in enumerate(doc.get("point", [])):
        name = t.get("name")
        if not isinstance(name, str) or not name.replace("-", "").replace(".", "").isalnum():
            raise GridError(f"{path}: [[point]] {i + 1}: 'name' must be a word of letters, digits, "
                            "'-' or '.'")
        if any(p.name == name for p in points):
            raise GridError(f"{path}: [[point]] {i + 1}: name '{name}' used twice")
        _check_knobs(path, f"[[point]] {i + 1} ({name})", t, require_all=False)
        changed = {k: v for k, v in t.items() if k != "name"}
        points.append(Point(name, {**ref, **changed}, changed))
    names = [p.name for p in problems]
    if len(set(names)) != len(names):
        raise GridError(f"{path}: two [[problem]] tables have the same name")
    return Grid(path, head.get("title", path), head.get("template", "configs/single-cell.toml"),
                problems, points)
