# SPDX-License-Identifier: MIT
"""Scene files for the frontier's points: the template (parsed TOML) with keys set by dotted
path, written back as TOML. Floats keep their shortest round-trip form (repr), so the programs read
exactly the value the grid gives (dld-sweep does the same, coupler/launcher/study.cpp)."""
import json
import tomllib


def read(path):
    with open(path, "rb") as f:
        return tomllib.load(f)


def set_key(doc, dotted, value):
    *tables, key = dotted.split(".")
    for t in tables:
        doc = doc.setdefault(t, {})
    doc[key] = value


def _value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return json.dumps(v)  # a TOML basic string for the characters scene files hold
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"scene value {v!r} cannot be written as TOML")


def _emit(lines, prefix, table):
    scalars = {k: v for k, v in table.items()
               if not isinstance(v, dict) and not (isinstance(v, list) and v and
                                                   all(isinstance(x, dict) for x in v))}
    if prefix and (scalars or not table):
        lines.append(f"[{prefix}]")
    for k, v in scalars.items():
        lines.append(f"{k} = {_value(v)}")
    for k, v in table.items():
        name = f"{prefix}.{k}" if prefix else k
        if isinstance(v, dict):
            _emit(lines, name, v)
        elif k not in scalars:
            for item in v:
                lines.append(f"[[{name}]]")
                lines.extend(f"{ik} = {_value(iv)}" for ik, iv in item.items())


def text(doc):
    lines = []
    _emit(lines, "", doc)
    return "\n".join(lines) + "\n"
