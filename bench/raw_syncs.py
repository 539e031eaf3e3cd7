#!/usr/bin/env python3
"""The disk's own rate of durable appends, the reference of bench/state_writes.sh: append a
record of about the state file's size to a file opened O_APPEND, fdatasync, again, for
SECONDS. The file is started afresh past 64 KiB, as the daemon's state file is compacted,
so both pay for a growing file's metadata alike. Prints JSON: syncs, seconds, per_second,
us_per_sync. Usage: raw_syncs.py FILE SECONDS"""
import json
import os
import sys
import time

path, seconds = sys.argv[1], float(sys.argv[2])
record = b"w 12288 1234 0a1b2c\n"
flags = os.O_WRONLY | os.O_CREAT | os.O_APPEND | os.O_TRUNC | os.O_CLOEXEC
fd = os.open(path, flags, 0o640)
size = syncs = 0
start = time.monotonic()
end = start + seconds
while True:
    os.write(fd, record)
    os.fdatasync(fd)
    syncs += 1
    size += len(record)
    if size > 64 * 1024:
        os.close(fd)
        fd = os.open(path, flags, 0o640)
        size = 0
    if syncs % 16 == 0 and time.monotonic() >= end:
        break
elapsed = time.monotonic() - start
os.close(fd)
os.unlink(path)
print(json.dumps({"syncs": syncs, "seconds": elapsed, "per_second": syncs / elapsed,
                  "us_per_sync": elapsed / syncs * 1e6}))
