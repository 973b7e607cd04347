#!/usr/bin/python3
"""analysis/interim_order.py: runs ordered least analysed first. Kept analyses: A 6.5 pillars,
B 2.0, C 0.3; D has none. The order "A B C D E" must become "D E C B A" (D and E, with none, keep
their order); without the file the order stays; a bad number (or nan) is refused with one line
naming the file and the run. Usage: interim_order_test.py PROJECT_SOURCE_DIR"""
import os
import subprocess
import sys
import tempfile

tool = os.path.join(sys.argv[1], "analysis", "interim_order.py")


def order(path, *runs):
    return subprocess.run([tool, path, *runs], capture_output=True, text=True)


def check(cond, what):
    if not cond:
        sys.exit(f"FAIL: {what}")


with tempfile.TemporaryDirectory() as tmp:
    kept = os.path.join(tmp, "summary-unfinished.csv")
    r = order(kept, "A", "B", "C", "D", "E")
    check(r.returncode == 0 and r.stdout.split() == list("ABCDE"), f"no file: {r.stdout}{r.stderr}")
    with open(kept, "w") as f:
        f.write("run,state,slowest_cell_pillars\nA,partial,6.5\nB,partial,2.0\nC,failed,0.3\n")
    r = order(kept, "A", "B", "C", "D", "E")
    check(r.returncode == 0 and r.stdout.split() == list("DECBA"), f"order: {r.stdout}{r.stderr}")
    for bad in ("lots", "nan"):
        with open(kept, "w") as f:
            f.write(f"run,state,slowest_cell_pillars\nA,partial,{bad}\n")
        r = order(kept, "A", "B")
        check(r.returncode != 0 and f"{kept}: run A: slowest_cell_pillars '{bad}'" in r.stderr
              and len(r.stderr.splitlines()) == 1, f"bad number {bad}: {r.stderr}")
print("ok")
