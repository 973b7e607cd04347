#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A membrane program written from docs/protocol.md alone, in Python with pyzmq.

It joins a fluid as one membrane peer, exchanges a few steps and ends the run. Node i of step s
sits at x = 0.5 i + s with force -0.25 i (exact in binary), and the test's fluid answers u = 2 x,
which this program checks bit for bit.

usage: python_membrane.py ENDPOINT STEPS NODES[,NODES...] HASH DX DT RHO LAMBDA RADIUS DEPTH SHIFT
"""
import struct
import sys

import zmq

MAGIC, VERSION = b"DLDC", 4
HELLO, WELCOME, STEP, VELOCITIES, SHUTDOWN, ERROR = 1, 2, 3, 4, 5, 6
HEADER = struct.Struct("<4sHHQQ")  # magic, version, type, step, payload bytes: 24 bytes
FIXED = struct.Struct("<Q11Id")  # handshake record, fixed part: 60 bytes (the last: contact halo)
# The values both sides agree on, by name (docs/protocol.md, "Handshake record").
NAMES = ["dx_m", "dt_s", "density_kg_m3", "lambda_m", "radius_m", "depth_m", "shift_m"]


def frame(kind, step, payload=b""):
    return HEADER.pack(MAGIC, VERSION, kind, step, len(payload)) + payload


def handshake(scene_hash, doubles, start_step, total_cells, name, index, count, first, cells):
    h, n = scene_hash.encode(), name.encode()
    values = b"".join(struct.pack("<I", len(k)) + k.encode() + struct.pack("<2d", v, 1e-12)
                      for k, v in zip(NAMES, doubles))
    fixed = FIXED.pack(start_step, total_cells, index, count, first, len(cells), len(h), len(n),
                       0, 0, len(NAMES), len(values), 0.0)  # no shared memory, surfaces, halo
    cell_faces = [0] * len(cells)
    return (fixed + values + h + n + struct.pack(f"<{len(cells)}I", *cells)
            + struct.pack(f"<{len(cells)}I", *cell_faces))


def receive(sock, timeout_ms=5000):
    if not sock.poll(timeout_ms):
        sys.exit("python membrane: no frame from the fluid within 5 s")
    data = sock.recv()
    magic, version, kind, step, size = HEADER.unpack_from(data)
    if magic != MAGIC or version != VERSION or size != len(data) - HEADER.size:
        sys.exit("python membrane: malformed frame from the fluid")
    if kind == ERROR:
        sys.exit(f"python membrane: fluid reported an error at step {step}: "
                 f"{data[HEADER.size:].decode(errors='replace')}")
    return kind, step, data[HEADER.size:]


def main():
    endpoint, steps = sys.argv[1], int(sys.argv[2])
    cells = [int(c) for c in sys.argv[3].split(",")]
    scene_hash, doubles = sys.argv[4], [float(v) for v in sys.argv[5:12]]
    nodes = sum(cells)
    sock = zmq.Context.instance().socket(zmq.PAIR)
    sock.setsockopt(zmq.LINGER, 2000)
    sock.connect(endpoint)
    sock.send(frame(HELLO, 0, handshake(scene_hash, doubles, 0, len(cells), "python-0", 0, 1, 0,
                                        cells)))
    kind, _, _ = receive(sock)
    if kind != WELCOME:
        sys.exit(f"python membrane: expected welcome, got frame type {kind}")
    for step in range(steps):
        x = [0.5 * i + step for i in range(3 * nodes)]
        f = [-0.25 * i for i in range(3 * nodes)]
        payload = struct.pack("<Q", nodes) + struct.pack(f"<{6 * nodes}d", *x, *f)
        sock.send(frame(STEP, step, payload))
        kind, reply_step, body = receive(sock)
        if kind != VELOCITIES or reply_step != step:
            sys.exit(f"python membrane: expected velocities of step {step}, got type {kind}")
        (count,) = struct.unpack_from("<Q", body)
        u = struct.unpack_from(f"<{3 * count}d", body, 8)
        if count != nodes or list(u) != [2 * v for v in x]:
            sys.exit(f"python membrane: wrong velocities at step {step}")
    sock.send(frame(SHUTDOWN, steps))
    sock.close()
    print(f"python membrane: {steps} steps exchanged")


if __name__ == "__main__":
    main()
