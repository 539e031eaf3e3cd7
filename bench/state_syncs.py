#!/usr/bin/env python3
"""The daemon's fdatasync rate while a load runs, from the state counters of its status
document (SPEC §10): read at DELAY seconds (after the load's warm-up) and SECONDS later.
Prints JSON: syncs_per_second, records_per_sync. Usage: state_syncs.py SOCKET DELAY SECONDS"""
import json
import socket
import sys
import time


def state(path):
    s = socket.socket(socket.AF_UNIX)
    s.connect(path)
    data = b""
    while chunk := s.recv(65536):
        data += chunk
    s.close()
    st = json.loads(data)["state"]
    return time.monotonic(), st["syncs"], st["records"]


path, delay, seconds = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
time.sleep(delay)
t0, syncs0, records0 = state(path)
time.sleep(seconds)
t1, syncs1, records1 = state(path)
syncs = syncs1 - syncs0
print(json.dumps({"syncs_per_second": syncs / (t1 - t0),
                  "records_per_sync": (records1 - records0) / syncs if syncs else 0}))
