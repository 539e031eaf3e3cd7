#!/usr/bin/env python3
"""What every feature together costs the Modbus TCP slave (issue 38, docs/performance.md).

Daemons fed alike on the feed transport (D1 changed 1,000 times a second by
bench/mqtt_feeder.py), each with FC4 x 64 on 127.0.0.1:
  minimal   - Modbus TCP and the feed, nothing else;
  all       - plus the state file, MQTT and Sparkplug B to a local mosquitto with a
              subscriber on each, and HTTP with the page's event stream open and /metrics
              scraped every second (bench/http_clients.py) during its rounds;
  all, no page     - the same daemon, nobody on HTTP during the round;
  all, no Sparkplug - a daemon like `all` without its sparkplug section, the page open.
While one daemon is measured the others and their feeders are stopped (SIGSTOP), so that
their features' work does not take the measured one's CPU on a small machine; it
settles for half a second after it resumes before the load starts.
At each connection count, paired rounds whose order turns each round; per round and
variant the requests/s (unima-bench-load) and the requests per daemon CPU-second (the
daemon's utime + stime over the load's run, /proc/PID/stat). Reports each variant's
median ratio to `minimal` (and the rounds' range), so the page's and Sparkplug's shares
are named. First, each variant's own cost without Modbus load: the daemon's CPU over
--idle seconds, alone, fed and watched as in its rounds (a sharper figure for a feature's
share than the rounds' ratios, whose range on 2 shared cores is wider than 5 %).
Usage: bench/all_features.py [--build-dir build-release] [--rounds 5] [--seconds 3]
       [--connections 8,64] [--json FILE]
"""
import argparse
import json
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SOURCE = Path(__file__).resolve().parent.parent
TICKS = os.sysconf("SC_CLK_TCK")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for_port(port, what, log=None, timeout=10.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
            return
        except OSError:
            time.sleep(0.05)
    sys.exit(f"{what} did not listen on {port}" + (f":\n{Path(log).read_text()}" if log else ""))


def cpu_seconds(pid):
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS  # utime, stime


class Bench:
    def __init__(self, args):
        self.args = args
        self.work = Path(tempfile.mkdtemp(prefix="all-features-"))
        build = Path(args.build_dir)
        self.bridged = build / "bin" / "unima-bridged"
        self.load = next(build.rglob("unima-bench-load"))
        self.processes = []

    def spawn(self, command, **kwargs):
        process = subprocess.Popen(command, **kwargs)
        self.processes.append(process)
        return process

    def close(self):
        for process in reversed(self.processes):
            if process.poll() is None:
                os.kill(process.pid, signal.SIGCONT)
            process.kill()
            process.wait()
        subprocess.run(["rm", "-rf", str(self.work)], check=False)

    def broker(self, extra=""):
        """`extra`: more lines of mosquitto.conf."""
        self.broker_port = free_port()
        conf = self.work / "broker.conf"
        conf.write_text(f"listener {self.broker_port} 127.0.0.1\nallow_anonymous true\npersistence false\nlog_dest none\n"
                        + extra)
        self.spawn(["mosquitto", "-c", str(conf)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wait_for_port(self.broker_port, "mosquitto")
        # A subscriber to everything the bridges publish: MQTT's documents and Sparkplug's.
        self.spawn(["mosquitto_sub", "-p", str(self.broker_port), "-t", "bench/#", "-t", "spBv1.0/#"],
                   stdout=subprocess.DEVNULL)

    def daemon(self, name, mqtt=False, sparkplug=False, http=False, state=False):
        modbus, feed = free_port(), free_port()
        lines = [
            f"unimabus: {{ transport: feed, listen: 127.0.0.1:{feed} }}",
            f"modbus: {{ tcp: {{ listen: 127.0.0.1, port: {modbus}, max_clients: 256 }} }}",
            "banks: { D1: 0x1100 }",
            "devices: { D1: { type: unigen-chp, address: 5 } }",
            "log: { level: warn }",
            f"status: {{ socket: {self.work / (name + '.sock')} }}",
            f"state: {{ file: {self.work / (name + '.state') if state else 'none'} }}",
        ]
        if mqtt:
            lines.append(f"mqtt: {{ broker: 'mqtt://127.0.0.1:{self.broker_port}', client_id: {name}-mqtt, topic: bench/{name} }}")
        if sparkplug:
            lines.append(f"sparkplug: {{ broker: 'mqtt://127.0.0.1:{self.broker_port}', client_id: {name}-sp, "
                         f"group_id: bench, edge_node_id: {name} }}")
        http_port = free_port() if http else None
        if http:
            lines.append(f"http: {{ listen: 127.0.0.1, port: {http_port} }}")
        config = self.work / f"{name}.yaml"
        config.write_text("\n".join(lines) + "\n")
        log = self.work / f"{name}.log"
        process = self.spawn([str(self.bridged), "--config", str(config)], stdout=log.open("w"), stderr=subprocess.STDOUT)
        wait_for_port(modbus, name, log)
        total = 2 * self.args.rounds * len(self.connections) * 4 * (self.args.seconds + 1) + 4 * (self.args.idle + 2) + 30
        feeder = self.spawn([sys.executable, str(SOURCE / "bench/mqtt_feeder.py"), "--feed-port", str(feed),
                             "--seconds", str(total)], stdout=subprocess.DEVNULL)
        return {"name": name, "pid": process.pid, "feeder": feeder.pid, "modbus": modbus, "http": http_port}

    def only(self, daemon):
        """Runs `daemon` and its feeder alone: the other daemons and feeders are stopped."""
        for other in self.daemons:
            sig = signal.SIGCONT if other is daemon else signal.SIGSTOP
            os.kill(other["feeder"], sig)
            os.kill(other["pid"], sig)
        time.sleep(0.5)

    def watched(self, daemon, page, seconds):
        """`daemon` alone, with the page open and /metrics scraped for `seconds` if `page`:
        the clients' process (wait for it after the measurement), or None."""
        self.only(daemon)
        if not page:
            return None
        clients = subprocess.Popen([sys.executable, str(SOURCE / "bench/http_clients.py"), "--port", str(daemon["http"]),
                                    "--seconds", str(seconds)], stdout=subprocess.DEVNULL)
        time.sleep(0.4)
        return clients

    def idle_cost(self, daemon, page):
        """The share of a core `daemon` takes with no Modbus load."""
        clients = self.watched(daemon, page, self.args.idle + 1)
        before = cpu_seconds(daemon["pid"])
        time.sleep(self.args.idle)
        share = (cpu_seconds(daemon["pid"]) - before) / self.args.idle
        if clients:
            clients.wait()
        return share

    def measure(self, daemon, connections, page):
        clients = self.watched(daemon, page, self.args.seconds + 1.5)
        before = cpu_seconds(daemon["pid"])
        out = subprocess.run([str(self.load), "--port", str(daemon["modbus"]), "--connections", str(connections),
                              "--function", "4", "--address", "4352", "--quantity", "64",
                              "--duration", str(self.args.seconds), "--warmup", "0.5", "--json"],
                             check=True, capture_output=True, text=True).stdout
        cpu = cpu_seconds(daemon["pid"]) - before
        if clients:
            clients.wait()
        result = json.loads(out)
        return {"rps": result["rps"], "per_cpu": result["total"] / cpu if cpu > 0 else float("nan")}

    def run(self):
        self.connections = [int(c) for c in self.args.connections.split(",")]
        self.broker()
        minimal = self.daemon("minimal")
        every = self.daemon("all", mqtt=True, sparkplug=True, http=True, state=True)
        no_sparkplug = self.daemon("nosp", mqtt=True, http=True, state=True)
        self.daemons = [minimal, every, no_sparkplug]
        time.sleep(1.5)  # connected, born, fed
        variants = [("minimal", minimal, False), ("all", every, True), ("all, no page", every, False),
                    ("all, no Sparkplug", no_sparkplug, True)]
        if self.args.idle > 0:
            print("without Modbus load, share of a core: " +
                  ", ".join(f"{name} {100 * self.idle_cost(daemon, page):.1f} %" for name, daemon, page in variants))
        figures = {}
        for connections in self.connections:
            rows = {name: [] for name, _, _ in variants}
            for round_ in range(self.args.rounds):
                order = variants if round_ % 2 == 0 else list(reversed(variants))
                for name, daemon, page in order:
                    rows[name].append(self.measure(daemon, connections, page))
                print(f"{connections} connections, round {round_ + 1}: " +
                      ", ".join(f"{n} {rows[n][-1]['rps']:,.0f}/s {rows[n][-1]['per_cpu']:,.0f}/cpu-s" for n in rows),
                      file=sys.stderr)
            figures[connections] = rows
        for name, daemon, _ in variants:
            for line in Path(self.work / f"{daemon['name']}.log").read_text().splitlines():
                if "error" in line.lower():
                    print(f"{daemon['name']}: {line}", file=sys.stderr)
        return figures


def ratios(rows, name, key):
    return [a[key] / b[key] for a, b in zip(rows[name], rows["minimal"])]


def report(figures, rounds):
    print(f"| variant | connections | requests/s (median) | ratio to minimal, requests/s | "
          f"ratio to minimal, requests per daemon CPU-second | rounds |")
    print("|---|---|---|---|---|---|")
    for connections, rows in figures.items():
        for name in rows:
            rps = statistics.median(r["rps"] for r in rows[name])
            if name == "minimal":
                print(f"| {name} | {connections} | {rps:,.0f} | | | {rounds} |")
                continue
            a, c = ratios(rows, name, "rps"), ratios(rows, name, "per_cpu")
            print(f"| {name} | {connections} | {rps:,.0f} | {statistics.median(a):.3f} ({min(a):.2f} – {max(a):.2f}) | "
                  f"{statistics.median(c):.3f} ({min(c):.2f} – {max(c):.2f}) | {rounds} |")
    print(f"\nload average at the end: {os.getloadavg()[0]:.2f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build-dir", default=str(SOURCE / "build-release"))
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--seconds", type=float, default=3)
    parser.add_argument("--connections", default="8,64")
    parser.add_argument("--idle", type=float, default=10, help="seconds of each variant without load (0: skip)")
    parser.add_argument("--json", metavar="FILE")
    args = parser.parse_args()
    bench = Bench(args)
    try:
        figures = bench.run()
    finally:
        bench.close()
    report(figures, args.rounds)
    if args.json:
        Path(args.json).write_text(json.dumps({str(k): v for k, v in figures.items()}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
