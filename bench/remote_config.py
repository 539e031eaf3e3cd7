#!/usr/bin/env python3
"""What a change of config from afar costs the Modbus clients (issue 40, docs/performance.md).

One daemon (sim transport, the state file, info logging as a site has it) serves plain
Modbus TCP on port P, Modbus/TCP Security on a second TCP port, and publishes to one of two
local mosquitto brokers; `remote_config: { probe: --probe }`. Config A has the TLS port on
Q1 and broker 1, config B the TLS port on Q2 and broker 2; both keep P. Two probers, each
on its own connection to P, read every 5 ms (FC3 of W, FC4 of D1) and time each answer; a
connection that breaks (reset, EOF) is a disconnect, a read unanswered for --limit seconds
a stall (each is counted, and the prober connects again).
Each round has five windows, in an order that turns every round (paired rounds):
  idle     --idle seconds of the probers alone;
  apply    `unima-bridge config apply` of the config not in force (A -> B, then B -> A the
           next round: every round moves the broker and the TLS port), timed from the CLI's
           start until it exits with its answer, and the probers' reads from that start
           until --tail seconds after the answer (the old connections' close, the birth);
  errors   --refused configs with an error (`max_clients: lots`), refused by the check;
  taken    --refused configs like the other one but whose TLS port is held by this bench
           (listening): the check passes and the stage fails to bind (refused);
  spawns   --refused runs of `unima-bridge config --help`, which asks the daemon nothing:
           the control, what the bench's own processes cost the probers on a small box.
Per round the p50 / p99 / max of each window, the ratios to idle's p99 (and the refused
windows' to the control's), the answer's time,
disconnects and stalls, the host's load average (the box is shared: say it). Then the
medians of the ratios and their range. The issue's targets: apply p99 <= 2 x idle, the
answer within probe + 1 s, refused configs within the noise, no disconnect on P.
Exits 1 when the behaviour fails: a disconnect or stall on P, an apply not `applied`, a
refusal not `refused`, the daemon gone; never for a time.
Usage: bench/remote_config.py [--build-dir build] [--rounds 5] [--idle 3] [--refused 100]
       [--probe 10] [--tail 1] [--limit 5] [--json FILE]
"""
import argparse
import json
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import all_features
from all_features import free_port, wait_for_port

sys.path.insert(0, str(all_features.SOURCE / "scripts"))
from soak import ModbusClient  # noqa: E402 (scripts/ is not a package)

PROBE_EVERY = 0.005
W_AT, D1_AT = 0x0100, 0x1100
TOPIC = "rcbench/site"
WINDOWS = ("idle", "apply", "errors", "taken", "spawns")


class Prober(threading.Thread):
    """Reads one block every PROBE_EVERY s on its own connection to `port` until stopped:
    (when sent, latency s) for each answer; a broken connection or a read unanswered for
    `limit` s is counted (disconnects, stalls) with its time, and the prober connects again."""

    def __init__(self, port, limit, function):
        super().__init__(daemon=True)
        self.port, self.limit, self.function = port, limit, function
        self.samples = []
        self.disconnects = []  # times of a reset or EOF on the connection
        self.stalls = []  # times of a read unanswered for `limit` seconds
        self.errors = []  # what broke, for the report
        self.stop = threading.Event()
        self.client = self.connect()

    def connect(self):
        client = ModbusClient(self.port, timeout=self.limit)
        client.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        return client

    def read(self):
        if self.function == 3:
            self.client.read_holding(W_AT, 4)
        else:
            self.client.read_input(D1_AT, 16)

    def run(self):
        next_at = time.perf_counter()
        while not self.stop.is_set():
            sent = time.perf_counter()
            try:
                self.read()
                self.samples.append((sent, time.perf_counter() - sent))
            except (TimeoutError, socket.timeout) as e:
                self.stalls.append(sent)
                self.errors.append(f"FC{self.function}: unanswered for {self.limit} s: {e}")
                self.reconnect()
            except OSError as e:
                # soak's client raises a Modbus exception as an OSError too: not a disconnect,
                # yet never right here (the reads are of served banks), so counted as a stall.
                (self.stalls if str(e).startswith("exception") else self.disconnects).append(sent)
                self.errors.append(f"FC{self.function}: {e}")
                self.reconnect()
            next_at = max(next_at + PROBE_EVERY, time.perf_counter())
            time.sleep(max(0.0, next_at - time.perf_counter()))

    def reconnect(self):
        self.client.close()
        for _ in range(50):  # 50 x 0.1 s: the port should never have gone away
            if self.stop.is_set():
                return
            try:
                self.client = self.connect()
                return
            except OSError:
                time.sleep(0.1)
        self.errors.append(f"FC{self.function}: could not connect again to port {self.port}")
        self.stop.set()

    def between(self, start, end):
        return [latency for sent, latency in self.samples if start <= sent < end]

    def count_between(self, events, start, end):
        return sum(1 for t in events if start <= t < end)


def figures(latencies):
    ms = sorted(x * 1000 for x in latencies)
    if len(ms) < 2:
        return {"reads": len(ms)}
    return {"reads": len(ms), "p50_ms": round(statistics.median(ms), 2),
            "p99_ms": round(statistics.quantiles(ms, n=100, method="inclusive")[98], 2), "max_ms": round(ms[-1], 2)}


def spread(values):
    values = [v for v in values if v is not None]
    if not values:
        return None
    return {"median": round(statistics.median(values), 2), "min": round(min(values), 2), "max": round(max(values), 2)}


class Bench(all_features.Bench):
    """all_features' spawning and clean-up (every process it started is killed, the
    temporary directory removed), two brokers and one daemon of its own."""

    def __init__(self, args):  # not all_features': no load generator here
        self.args = args
        self.work = Path(tempfile.mkdtemp(prefix="remote-config-"))
        self.processes = []
        self.held = None

    def close(self):
        if self.held:
            self.held.close()
        super().close()

    def start_broker(self, name):
        port = free_port()
        conf = self.work / f"{name}.conf"
        conf.write_text(f"listener {port} 127.0.0.1\nallow_anonymous true\npersistence false\nlog_dest none\n")
        self.spawn(["mosquitto", "-c", str(conf)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wait_for_port(port, f"mosquitto ({name})")
        return port

    def config_text(self, tls_port, broker_port, error=False):
        certs = self.work / "certs"
        return (
            "unimabus: { transport: sim }\n"
            "modbus:\n"
            f"  tcp: {{ listen: 127.0.0.1, port: {self.plain}{', max_clients: lots' if error else ''} }}\n"
            f"  tls: {{ listen: 127.0.0.1, port: {tls_port}, certificate: {certs}/server.pem, key: {certs}/server.key,\n"
            f"         ca: {certs}/ca.pem, roles: {{ operator: {{ write: [W] }} }} }}\n"
            f"banks: {{ D1: 0x{D1_AT:04X}, W: 0x{W_AT:04X} }}\n"
            "devices: { D1: { type: unigen-chp, address: 5 } }\n"
            "log: { level: info }\n"
            f"status: {{ socket: {self.socket} }}\n"
            f"state: {{ file: {self.work / 'bridge.state'} }}\n"
            f"mqtt: {{ broker: 'mqtt://127.0.0.1:{broker_port}', client_id: rcbench, topic: {TOPIC}, buffer: {{ file: none }} }}\n"
            f"remote_config: {{ probe: {self.args.probe}s }}\n")

    def start(self):
        subprocess.run([str(all_features.SOURCE / "tests/integration/tls/make_certificates.sh"), str(self.work / "certs")],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=60)
        brokers = [self.start_broker("broker1"), self.start_broker("broker2")]
        self.plain, self.socket = free_port(), self.work / "bridge.sock"
        tls_ports = [free_port(), free_port()]
        # The port a refused config asks for: this bench listens on it, so the stage cannot bind it.
        self.held = socket.socket()
        self.held.bind(("127.0.0.1", 0))
        self.held.listen(1)
        taken = self.held.getsockname()[1]
        self.configs = {}
        for name, tls_port, broker in (("A", tls_ports[0], brokers[0]), ("B", tls_ports[1], brokers[1])):
            path = self.work / f"{name}.yaml"
            path.write_text(self.config_text(tls_port, broker))
            self.configs[name] = {"path": path, "tls": tls_port, "broker": broker}
        self.errors_config = self.work / "errors.yaml"
        self.errors_config.write_text(self.config_text(tls_ports[1], brokers[1], error=True))
        self.taken_config = self.work / "taken.yaml"
        self.taken_config.write_text(self.config_text(taken, brokers[1]))
        self.log = self.work / "bridge.log"
        bridged = Path(self.args.build_dir) / "bin" / "unima-bridged"
        self.cli = Path(self.args.build_dir) / "bin" / "unima-bridge"
        self.daemon = self.spawn([str(bridged), "--config", str(self.configs["A"]["path"])], stdout=self.log.open("w"),
                                 stderr=subprocess.STDOUT)
        wait_for_port(self.plain, "unima-bridged", self.log)
        wait_for_port(tls_ports[0], "unima-bridged's TLS port", self.log)
        deadline = time.monotonic() + 10
        while "mqtt: connected" not in self.log.read_text():
            if time.monotonic() > deadline or self.daemon.poll() is not None:
                sys.exit("the daemon did not connect to broker 1:\n" + self.log.read_text())
            time.sleep(0.05)
        self.in_force = "A"
        self.probers = [Prober(self.plain, self.args.limit, 3), Prober(self.plain, self.args.limit, 4)]
        for prober in self.probers:
            prober.start()
        time.sleep(0.5)  # the probers' first reads (connections warm) are not measured

    def config_apply(self, path):
        """The CLI's answer to `config apply path`: (result, seconds from its start to its exit, reason)."""
        start = time.perf_counter()
        done = subprocess.run([str(self.cli), "config", "apply", str(path), "--socket", str(self.socket), "--json",
                               "--timeout", str(self.args.probe + 30)],
                              capture_output=True, text=True, timeout=self.args.probe + 40)
        seconds = time.perf_counter() - start
        try:
            answer = json.loads(done.stdout)
        except json.JSONDecodeError:
            return "no answer: " + (done.stdout + done.stderr).strip(), seconds, ""
        return answer.get("result"), seconds, answer.get("reason", "")

    def measured(self, start, end):
        latencies = [x for p in self.probers for x in p.between(start, end)]
        return {**figures(latencies),
                "disconnects": sum(p.count_between(p.disconnects, start, end) for p in self.probers),
                "stalls": sum(p.count_between(p.stalls, start, end) for p in self.probers)}

    def idle_window(self):
        start = time.perf_counter()
        time.sleep(self.args.idle)
        return self.measured(start, time.perf_counter())

    def apply_window(self):
        target = "B" if self.in_force == "A" else "A"
        start = time.perf_counter()
        result, seconds, reason = self.config_apply(self.configs[target]["path"])
        time.sleep(self.args.tail)
        window = self.measured(start, time.perf_counter())
        if result == "applied":
            self.in_force = target
        moved = None
        try:  # the new TLS port listens: the move happened
            socket.create_connection(("127.0.0.1", self.configs[target]["tls"]), timeout=1).close()
            moved = True
        except OSError:
            moved = False
        return {**window, "move": f"{'AB'.replace(target, '')}->{target}", "result": result, "reason": reason,
                "answer_s": round(seconds, 3), "new_tls_port_listens": moved}

    def refused_window(self, path):
        results = []
        start = time.perf_counter()
        for _ in range(self.args.refused):
            result, seconds, _ = self.config_apply(path)
            results.append((result, seconds))
        window = self.measured(start, time.perf_counter())
        return {**window, "refused": sum(1 for r, _ in results if r == "refused"), "sent": len(results),
                "others": sorted({r for r, _ in results if r != "refused"}),
                "answer_s_median": round(statistics.median(s for _, s in results), 3)}

    def spawns_window(self):
        start = time.perf_counter()
        for _ in range(self.args.refused):
            subprocess.run([str(self.cli), "config", "--help"], stdout=subprocess.DEVNULL, check=True, timeout=10)
        return self.measured(start, time.perf_counter())

    def round(self, number):
        log_before = self.log.read_text().count("\n")
        windows = {
            "idle": self.idle_window,
            "apply": self.apply_window,
            "errors": lambda: self.refused_window(self.errors_config),
            "taken": lambda: self.refused_window(self.taken_config),
            "spawns": self.spawns_window,
        }
        order = list(windows) if number % 2 == 0 else list(reversed(windows))
        result = {"round": number + 1, "order": order}
        for name in order:
            result[name] = windows[name]()
        idle_p99 = result["idle"].get("p99_ms")
        for name in ("apply", "errors", "taken", "spawns"):
            p99 = result[name].get("p99_ms")
            result[f"{name}_p99_ratio"] = round(p99 / idle_p99, 2) if p99 and idle_p99 else None
        spawns_p99 = result["spawns"].get("p99_ms")
        for name in ("errors", "taken"):
            p99 = result[name].get("p99_ms")
            result[f"{name}_p99_to_spawns"] = round(p99 / spawns_p99, 2) if p99 and spawns_p99 else None
        result["log_lines"] = self.log.read_text().count("\n") - log_before
        result["load"] = [round(x, 2) for x in os.getloadavg()]
        return result


def summary(rounds, args):
    applies = [r["apply"] for r in rounds]
    return {
        "rounds": len(rounds),
        "probe_s": args.probe,
        "apply_p99_ratio": spread([r["apply_p99_ratio"] for r in rounds]),
        "errors_p99_ratio": spread([r["errors_p99_ratio"] for r in rounds]),
        "taken_p99_ratio": spread([r["taken_p99_ratio"] for r in rounds]),
        "spawns_p99_ratio": spread([r["spawns_p99_ratio"] for r in rounds]),
        "errors_p99_to_spawns": spread([r["errors_p99_to_spawns"] for r in rounds]),
        "taken_p99_to_spawns": spread([r["taken_p99_to_spawns"] for r in rounds]),
        "idle_p99_ms": spread([r["idle"].get("p99_ms") for r in rounds]),
        "apply_max_ms": spread([a.get("max_ms") for a in applies]),
        "answer_s": spread([a["answer_s"] for a in applies]),
        "answers_within_probe_plus_1s": sum(1 for a in applies if a["answer_s"] <= args.probe + 1),
        "applied": sum(1 for a in applies if a["result"] == "applied"),
        "refused": sum(r[w]["refused"] for r in rounds for w in ("errors", "taken")),
        "refusals_sent": sum(r[w]["sent"] for r in rounds for w in ("errors", "taken")),
        "disconnects": sum(r[w]["disconnects"] for r in rounds for w in WINDOWS),
        "stalls": sum(r[w]["stalls"] for r in rounds for w in WINDOWS),
        "load_1min": spread([r["load"][0] for r in rounds]),
    }


def failures(bench, rounds, total):
    """The behaviour the bench asserts (never a time)."""
    found = []
    if total["applied"] != len(rounds):
        found.append(f"{len(rounds) - total['applied']} apply(s) not answered applied: "
                     + "; ".join(f"{r['apply']['result']} {r['apply']['reason']}" for r in rounds if r["apply"]["result"] != "applied"))
    if total["refused"] != total["refusals_sent"]:
        found.append(f"{total['refusals_sent'] - total['refused']} bad config(s) not answered refused")
    if not all(r["apply"]["new_tls_port_listens"] for r in rounds):
        found.append("an applied config's TLS port did not listen")
    if total["disconnects"] or total["stalls"]:
        errors = [e for p in bench.probers for e in p.errors]
        found.append(f"{total['disconnects']} disconnect(s) and {total['stalls']} stall(s) on the unchanged port: {errors[:5]}")
    if any(r[w].get("reads", 0) < 2 for r in rounds for w in WINDOWS):
        found.append("a window without reads")
    if bench.daemon.poll() is not None:
        found.append(f"the daemon exited ({bench.daemon.returncode})")
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build-dir", default="build")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--idle", type=float, default=3, help="seconds of the idle window")
    parser.add_argument("--refused", type=int, default=100, help="refused configs per refused window (each kind)")
    parser.add_argument("--probe", type=int, default=10, help="remote_config.probe of both configs, seconds")
    parser.add_argument("--tail", type=float, default=1, help="seconds the apply window runs on after the answer")
    parser.add_argument("--limit", type=float, default=5, help="seconds a read may wait before it counts as a stall")
    parser.add_argument("--json", help="write the rounds and the summary here too")
    args = parser.parse_args()
    bench = Bench(args)
    rounds = []
    try:
        bench.start()
        print(f"load average at the start: {' '.join(f'{x:.2f}' for x in os.getloadavg())}", file=sys.stderr)
        for n in range(args.rounds):
            rounds.append(bench.round(n))
            print(json.dumps(rounds[-1]), flush=True)
            if bench.daemon.poll() is not None:
                break
        total = summary(rounds, args)
        print(json.dumps({"summary": total}), flush=True)
        found = failures(bench, rounds, total)
        if args.json:
            Path(args.json).write_text(json.dumps({"rounds": rounds, "summary": total, "failures": found}, indent=1) + "\n")
        for p in bench.probers:
            p.stop.set()
        for p in bench.probers:
            p.join(timeout=args.limit + 1)
        if found:
            print("FAILED:\n  " + "\n  ".join(found) + "\n--- the daemon's log:\n" + bench.log.read_text()[-4000:], file=sys.stderr)
            return 1
    finally:
        for p in getattr(bench, "probers", []):
            p.stop.set()
        bench.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
