#!/usr/bin/env python3
"""Instructions per FC4 request of one or more builds of unima-bridged, counted by
callgrind, so that two builds compare on a busy machine where requests/s would not
(issue 38: the plain path against a fixed older commit, bench/against_commit.sh).

Each build serves bench/configs/bridge.yaml (or --bridge-config) under
`valgrind --tool=callgrind`; unima-bench-load makes --small and then, in a second run,
--large requests (64 x FC4 of 64 registers, as run_bench.py's exact counts); the
difference of the two totals over the difference of the requests cancels start-up and
shutdown. Prints a table, the first build as the reference, and keeps the callgrind files
with --keep DIR (for callgrind_annotate).
Usage: bench/instructions.py --load build/bench/unima-bench-load NAME=PATH/unima-bridged [NAME=PATH ...]
"""
import argparse
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SOURCE = Path(__file__).resolve().parent.parent


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def total_instructions(path):
    for line in path.read_text().splitlines():
        if line.startswith(("summary:", "totals:")):
            return int(line.split()[1])
    sys.exit(f"no instruction total in {path}")


def counted_run(bridged, config_template, load, work, name, requests, connections):
    modbus, feed = free_port(), free_port()
    config = work / f"{name}-{requests}.yaml"
    config.write_text(config_template.replace("@MODBUS_PORT@", str(modbus)).replace("@FEED_PORT@", str(feed))
                      .replace("@DIR@", str(work)))
    out = work / f"callgrind-{name}-{requests}.out"
    log = (work / f"{name}-{requests}.log").open("w")
    daemon = subprocess.Popen(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", "--quiet",
                               str(bridged), "--config", str(config)], stdout=log, stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + 120
        while True:
            try:
                socket.create_connection(("127.0.0.1", modbus), timeout=0.5).close()
                break
            except OSError:
                if time.monotonic() > deadline or daemon.poll() is not None:
                    sys.exit(f"{name} did not start: {(work / f'{name}-{requests}.log').read_text()}")
                time.sleep(0.2)
        subprocess.run([str(load), "--port", str(modbus), "--connections", str(connections), "--function", "4",
                        "--address", "0x1100", "--quantity", "64", "--duration", "0", "--requests", str(requests), "--timeout", "600",
                        "--json"], check=True, capture_output=True, timeout=1200)
    finally:
        daemon.terminate()
        daemon.wait(timeout=120)
    return total_instructions(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("builds", nargs="+", metavar="NAME=PATH")
    parser.add_argument("--load", required=True, help="unima-bench-load")
    parser.add_argument("--bridge-config", default=str(SOURCE / "bench/configs/bridge.yaml"))
    parser.add_argument("--small", type=int, default=20000)
    parser.add_argument("--large", type=int, default=60000)
    parser.add_argument("--connections", type=int, default=64)
    parser.add_argument("--keep", metavar="DIR", help="copy the callgrind files here")
    args = parser.parse_args()
    if not shutil.which("valgrind"):
        sys.exit("valgrind is not installed (scripts/install-deps.sh installs it)")
    template = Path(args.bridge_config).read_text()
    work = Path(tempfile.mkdtemp(prefix="instructions-"))
    rows = []
    try:
        for build in args.builds:
            name, _, path = build.partition("=")
            a = counted_run(path, template, args.load, work, name, args.small, args.connections)
            b = counted_run(path, template, args.load, work, name, args.large, args.connections)
            rows.append((name, (b - a) / (args.large - args.small)))
            print(f"{name}: {rows[-1][1]:,.0f} instructions per request", file=sys.stderr)
        if args.keep:
            Path(args.keep).mkdir(parents=True, exist_ok=True)
            for f in work.glob("callgrind-*.out"):
                shutil.copy(f, args.keep)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"| build | instructions per request ({args.connections} connections, FC4 x 64) | against {rows[0][0]} |")
    print("|---|---|---|")
    for name, per_request in rows:
        print(f"| {name} | {per_request:,.0f} | {per_request / rows[0][1]:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
