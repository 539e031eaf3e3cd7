#!/usr/bin/env bash
# How fast `unima-bridge monitor --pcap` turns a monitor log into a pcap file (SPEC §20,
# issue 42): a ~100 MB log of the monitor's text lines (TCP reads of 64 registers, writes,
# exceptions, RTU lines with a Not4Me and a bad CRC), converted to a file, beside
# `cat LOG > /dev/null` as the limit of reading it. Reports MB/s of log read; the target
# is at least 50 MB/s. The log is made once per run in a temporary directory.
# Usage: bench/pcap.sh [BUILD_DIR] [LOG_MB]   (default build-release 100)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-release}
size_mb=${2:-100}
cli=$build/bin/unima-bridge
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 - "$work/monitor.log" "$size_mb" <<'PY'
import sys
path, size = sys.argv[1], int(sys.argv[2]) * 1_000_000
regs = " ".join("00 50" for _ in range(64))
lines = [
    "Ix={ix} Rc=12 State=Done TrID={tr:04X} PtID=0000 Len=0006 Ad=1 PDU=04 11 00 00 40 "
    "Response={trh} {trl} 00 00 00 83 01 04 80 " + regs,
    "Ix={ix} Rc=17 State=Done TrID={tr:04X} PtID=0000 Len=000B Ad=1 PDU=10 01 00 00 02 04 09 29 00 07 "
    "Response={trh} {trl} 00 00 00 06 01 10 01 00 00 02",
    "Ix={ix} Rc=12 State=Err02 TrID={tr:04X} PtID=0000 Len=0006 Ad=1 PDU=04 12 00 00 01 "
    "Response={trh} {trl} 00 00 00 03 01 84 02",
]
rtu = [
    "rtu Ix={ix} Rc=8 State=Not4Me Ad=3 PDU=04 02 00 00 01 CRC=3190 Response=03 04 02 01 2C C0 BD",
    "rtu Ix={ix} Rc=8 State=Err03 Ad=1 PDU=04 01 00 00 01 CRC=3026 Response=-",
]
written, n = 0, 0
with open(path, "w") as out:
    while written < size:
        second, micro = divmod(n * 250, 1_000_000)
        stamp = f"2026-11-28T{8 + second // 3600:02d}:{second // 60 % 60:02d}:{second % 60:02d}.{micro:06d}Z"
        tr = n % 65536
        if n % 10 == 9:
            body = rtu[n // 10 % 2].format(ix=n % 256)
        else:
            body = f"tcp:10.0.0.{n % 7 + 2}:{40000 + n % 500} " + lines[n % 3].format(
                ix=n % 256, tr=tr, trh=f"{tr >> 8:02X}", trl=f"{tr & 255:02X}")
        line = f"{stamp} {body}\n"
        out.write(line)
        written += len(line)
        n += 1
PY

seconds() {  # the wall time of a command, in seconds
  local start end
  start=$(date +%s.%N)
  "$@"
  end=$(date +%s.%N)
  python3 -c "print($end - $start)"
}
bytes=$(stat -c %s "$work/monitor.log")
cat "$work/monitor.log" > /dev/null  # in the page cache for both
cat_s=$(seconds sh -c "cat '$work/monitor.log' > /dev/null")
pcap_s=$(seconds "$cli" monitor --pcap "$work/out.pcap" "$work/monitor.log")
python3 - "$bytes" "$cat_s" "$pcap_s" "$(stat -c %s "$work/out.pcap")" <<'PY'
import sys
size, cat_s, pcap_s, out = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
mb = size / 1e6
print(f"pcap: log {mb:.1f} MB -> pcap {out / 1e6:.1f} MB")
print(f"  cat > /dev/null          {mb / cat_s:9.1f} MB/s")
print(f"  unima-bridge --pcap      {mb / pcap_s:9.1f} MB/s  (target >= 50)")
PY
