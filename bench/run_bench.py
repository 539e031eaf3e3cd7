#!/usr/bin/env python3
"""Runs unima-bridged and the libmodbus reference server side by side (docs/performance.md).

Every server gets a free loopback port. The throughput runs alternate between the servers
(A B A B ..., one round = one run of each) and every figure compared is the median of the
per-round ratios, because the machine is shared and absolute rates swing between runs.
CPU time and peak RSS come from /proc; system calls and user-space instructions per
request are exact counts: the difference between two runs with different request counts
under `strace -c -f` and `valgrind --tool=callgrind`, so start-up and shutdown cancel.

Standard library only. Exit code 0 when every tool ran and every response was right;
1 otherwise. No time is ever asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

BENCH_DIR = Path(__file__).resolve().parent
SOURCE_DIR = BENCH_DIR.parent
CLOCK_TICKS = os.sysconf("SC_CLK_TCK")

# What the load reads: bank D1 of bench/configs/bridge.yaml, the whole 64-register table.
READ_ADDRESS = 0x1100
READ_COUNT = 64


class BenchError(Exception):
    pass


_next_port = 10000 + os.getpid() * 7919 % 20000


def free_port() -> int:
    """A loopback port below the kernel's ephemeral range (32768 by default): one from
    bind(0) may become a load connection's local port before the server binds it."""
    global _next_port
    for _ in range(20000):
        port = 10000 + (_next_port - 10000) % 20000
        _next_port += 1
        with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
            try:
                s.bind(("127.0.0.1", port))
            except OSError:
                continue
            return port
    raise BenchError("no free loopback port from 10000 to 29999")


def wait_for_port(port: int, process: subprocess.Popen, what: str, timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise BenchError(f"{what} exited with code {process.returncode} before listening")
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.5):
                return
        except OSError:
            time.sleep(0.02)
    raise BenchError(f"{what} did not listen on port {port} within {timeout} s")


@dataclass
class ServerKind:
    """A server under test: how to start it on given ports."""

    name: str
    reference: bool = False
    config_template: Path | None = None  # a bridge config with @MODBUS_PORT@ etc.
    binary: str | None = None  # another build of the daemon than tools.bridged (--other-bridged)

    def command(self, tools: "Tools", workdir: Path, modbus_port: int, feed_port: int) -> list[str]:
        if self.reference:
            return [tools.reference, "--port", str(modbus_port), "--address", hex(READ_ADDRESS),
                    "--count", str(READ_COUNT)]
        text = self.config_template.read_text()
        text = text.replace("@MODBUS_PORT@", str(modbus_port)).replace("@FEED_PORT@", str(feed_port))
        text = text.replace("@DIR@", str(self.directory(workdir, modbus_port)))
        config = workdir / f"{self.name}-{modbus_port}.yaml"
        config.write_text(text)
        return [self.binary or tools.bridged, "--config", str(config)]

    def directory(self, workdir: Path, modbus_port: int) -> Path:
        """@DIR@: each daemon's own, so that no two share a control socket or monitor log."""
        path = workdir / f"{self.name.replace(':', '-')}-{modbus_port}"
        path.mkdir(exist_ok=True)
        return path


class Server:
    """A running server; `wrapper` runs it under strace or valgrind."""

    def __init__(self, kind: ServerKind, tools: "Tools", workdir: Path, wrapper: list[str] | None = None,
                 start_timeout: float = 10):
        self.kind = kind
        self.modbus_port = free_port()
        self.feed_port = free_port()
        self.log_path = workdir / f"{kind.name}-{self.modbus_port}.log"
        command = kind.command(tools, workdir, self.modbus_port, self.feed_port)
        # Where a daemon's config puts its status socket (`@DIR@/control.sock`); None for the reference.
        self.control_socket = (None if kind.reference
                               else kind.directory(workdir, self.modbus_port) / "control.sock")
        self.wrapped = wrapper is not None
        self.log = open(self.log_path, "w")
        self.process = subprocess.Popen((wrapper or []) + command, stdout=self.log, stderr=subprocess.STDOUT,
                                        stdin=subprocess.DEVNULL)
        try:
            wait_for_port(self.modbus_port, self.process, kind.name, start_timeout)
        except BenchError as e:
            self.stop()
            raise BenchError(f"{e}; its output:\n{self.output()}") from None
        self.pid = self.server_pid()

    def server_pid(self) -> int:
        """The server's own pid: strace runs it as a child, valgrind in its own process."""
        if not self.wrapped or "valgrind" in self.process.args[0]:
            return self.process.pid
        children = Path(f"/proc/{self.process.pid}/task/{self.process.pid}/children").read_text().split()
        if len(children) != 1:
            raise BenchError(f"cannot find the server under {self.process.args[0]}")
        return int(children[0])

    def control_status(self) -> dict | None:
        """The daemon's status document (its control socket, `status.socket`), if it has one."""
        if self.control_socket is None or not self.control_socket.exists():
            return None
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
            s.settimeout(5)
            s.connect(str(self.control_socket))
            data = b""
            while chunk := s.recv(65536):
                data += chunk
        return json.loads(data)

    def monitor_dropped(self) -> int | None:
        """Monitor lines dropped so far, when this daemon writes a monitor log."""
        status = self.control_status()
        return status["monitor"]["dropped"] if status and status["monitor"]["file"] else None

    def output(self) -> str:
        if not self.log.closed:
            self.log.flush()
        return self.log_path.read_text()[-4000:]

    def cpu_times(self) -> tuple[float, float]:
        """User and system CPU seconds so far."""
        fields = Path(f"/proc/{self.pid}/stat").read_text().rsplit(")", 1)[1].split()
        return int(fields[11]) / CLOCK_TICKS, int(fields[12]) / CLOCK_TICKS  # utime, stime

    def cpu_seconds(self) -> float:
        return sum(self.cpu_times())

    def status(self, key: str) -> int:
        for line in Path(f"/proc/{self.pid}/status").read_text().splitlines():
            if line.startswith(key + ":"):
                return int(line.split()[1])
        raise BenchError(f"no {key} in /proc/{self.pid}/status")

    def stop(self, timeout: float = 20) -> None:
        """SIGTERM, and the exit awaited; a server that has not stopped within `timeout` is
        killed and reported: a stop that hangs is a fault to see, not a time to wait out."""
        overran = False
        if self.process.poll() is None:
            try:
                os.kill(getattr(self, "pid", self.process.pid), signal.SIGTERM)
                self.process.wait(timeout=timeout)
            except ProcessLookupError:
                pass
            except subprocess.TimeoutExpired:
                overran = True
                self.process.kill()
                self.process.wait()
        self.log.close()
        if overran:
            raise BenchError(f"{self.kind.name} did not stop within {timeout} s of SIGTERM (killed); "
                             f"its output:\n{self.output()}")


@dataclass
class Tools:
    bridged: str
    load: str
    reference: str
    propagation: str


@dataclass
class Settings:
    rounds: int
    duration: float
    warmup: float
    connections: list[int]
    depths: list[int]
    exact_connections: int
    exact_requests: tuple[int, int]
    idle_seconds: float
    changes: int
    callgrind: bool
    strace: bool
    pin: str = "none"  # none | apart | same: the CPUs of server and load in the throughput runs

    def load_cpu(self) -> int | None:
        return {"apart": 1, "same": 0}.get(self.pin)


def run_load(tools: Tools, port: int, connections: int, depth: int, *, duration: float = 0, warmup: float = 0,
             requests: int = 0, timeout: float = 600, cpu: int | None = None) -> dict:
    command = [tools.load, "--port", str(port), "--connections", str(connections), "--depth", str(depth),
               "--function", "4", "--address", hex(READ_ADDRESS), "--quantity", str(READ_COUNT),
               "--duration", str(duration), "--warmup", str(warmup), "--requests", str(requests), "--json"]
    pin = (lambda: os.sched_setaffinity(0, {cpu})) if cpu is not None else None
    result = subprocess.run(command, capture_output=True, text=True, timeout=timeout, preexec_fn=pin)
    if result.returncode != 0:
        raise BenchError(f"load generator failed: {result.stderr.strip()}")
    report = json.loads(result.stdout)
    if report["requests"] == 0:
        raise BenchError(f"load generator completed no request: {result.stdout}")
    return report


# --- throughput and latency, paired runs ------------------------------------------------

@dataclass
class Cell:
    """The runs of one server at one connection count and depth."""

    runs: list[dict] = field(default_factory=list)

    def median(self, key: str) -> float:
        return statistics.median(r[key] for r in self.runs)


def throughput(kinds: list[ServerKind], tools: Tools, workdir: Path, settings: Settings) -> tuple[dict, dict]:
    servers: list[Server] = []
    cells: dict[tuple[int, int, str], Cell] = {}
    resources: dict[str, dict] = {}
    try:
        for kind in kinds:
            servers.append(Server(kind, tools, workdir))
            if settings.pin != "none":
                os.sched_setaffinity(servers[-1].pid, {0})
        for depth in settings.depths:
            for connections in settings.connections:
                for round_number in range(settings.rounds):
                    for server in servers:  # A B A B ...
                        dropped_before = server.monitor_dropped()
                        user_before, system_before = server.cpu_times()
                        report = run_load(tools, server.modbus_port, connections, depth,
                                          duration=settings.duration, warmup=settings.warmup, cpu=settings.load_cpu())
                        user, system = server.cpu_times()
                        if dropped_before is not None:  # a variant with the monitor log: were lines lost?
                            report["monitor_dropped"] = server.monitor_dropped() - dropped_before
                        report["cpu_us_per_request"] = (user + system - user_before - system_before) * 1e6 / report["total"]
                        report["user_cpu_us_per_request"] = (user - user_before) * 1e6 / report["total"]
                        cells.setdefault((depth, connections, server.kind.name), Cell()).runs.append(report)
                    progress(f"depth {depth}, {connections} connections, round {round_number + 1}/{settings.rounds}: "
                             + ", ".join(f"{s.kind.name} {cells[(depth, connections, s.kind.name)].runs[-1]['rps']:.0f}/s"
                                         for s in servers))
        progress("idle check")
        for server in servers:
            resources[server.kind.name] = idle_check(server, settings.idle_seconds, max(settings.connections))
            resources[server.kind.name]["peak_rss_kib"] = server.status("VmHWM")
    finally:
        for server in servers:
            server.stop()
    return cells, resources


def settle(server: Server) -> None:
    """Waits until the server has stopped switching in (closing connections, accepting)."""
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline:
        switches = server.status("voluntary_ctxt_switches")
        time.sleep(0.2)
        if server.status("voluntary_ctxt_switches") == switches:
            return


def quiet_period(server: Server, seconds: float) -> tuple[float, int]:
    """CPU milliseconds and wake-ups (context switches) of the server over `seconds`."""
    def switches() -> int:
        return server.status("voluntary_ctxt_switches") + server.status("nonvoluntary_ctxt_switches")
    cpu, before = server.cpu_seconds(), switches()
    time.sleep(seconds)
    return (server.cpu_seconds() - cpu) * 1e3, switches() - before


def idle_check(server: Server, seconds: float, clients: int) -> dict:
    """Idle costs nothing: no client, then `clients` connected clients that send nothing."""
    settle(server)
    idle_cpu, idle_wakeups = quiet_period(server, seconds)
    sockets = [socket.create_connection(("127.0.0.1", server.modbus_port)) for _ in range(clients)]
    try:
        settle(server)
        connected_cpu, connected_wakeups = quiet_period(server, seconds)
    finally:
        for s in sockets:
            s.close()
    return {"idle_seconds": seconds, "idle_cpu_ms": idle_cpu, "idle_wakeups": idle_wakeups,
            "idle_clients": clients, "idle_clients_cpu_ms": connected_cpu, "idle_clients_wakeups": connected_wakeups}


def round_ratios(cells: dict, depth: int, connections: int, name: str, reference: str, key: str) -> list[float]:
    """name/reference for `key`, paired round by round."""
    mine = cells[(depth, connections, name)].runs
    theirs = cells[(depth, connections, reference)].runs
    return [a[key] / b[key] for a, b in zip(mine, theirs) if b[key] > 0]


def ratios(cells: dict, depth: int, connections: int, name: str, reference: str, key: str) -> float:
    """The median over rounds of name/reference for `key`, paired round by round."""
    return statistics.median(round_ratios(cells, depth, connections, name, reference, key))


def quartiles(values: list[float]) -> str:
    """" (rounds a – b)": where the middle half of the per-round ratios lie, so that a reader
    sees how far this run's median could move in the next one."""
    if len(values) < 4:
        return ""
    q1, _, q3 = statistics.quantiles(values, n=4)
    return f" (rounds {q1:.2f} – {q3:.2f})"


# --- exact counts -------------------------------------------------------------------------

def strace_counts(path: Path) -> dict[str, int]:
    calls: dict[str, int] = {}
    for line in path.read_text().splitlines():
        parts = line.split()
        if len(parts) >= 5 and re.fullmatch(r"[\d.]+", parts[0]) and parts[3].isdigit():
            calls[parts[-1]] = int(parts[3])
    if "total" not in calls:
        raise BenchError(f"no total in the strace summary {path}")
    return calls


def callgrind_instructions(path: Path) -> int:
    for line in path.read_text().splitlines():
        if line.startswith(("summary:", "totals:")):
            return int(line.split()[1])
    raise BenchError(f"no instruction total in {path}")


def exact_run(kind: ServerKind, tools: Tools, workdir: Path, settings: Settings, tool: str, requests: int) -> Path:
    out = workdir / f"{tool}-{kind.name}-{requests}.out"
    if tool == "strace":
        wrapper = ["strace", "-f", "-c", "-o", str(out), "--"]
    else:
        wrapper = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", "--quiet"]
    server = Server(kind, tools, workdir, wrapper, start_timeout=120)
    try:
        run_load(tools, server.modbus_port, settings.exact_connections, 1, requests=requests)
    finally:
        server.stop(timeout=60)
    if server.process.returncode != 0:
        raise BenchError(f"{kind.name} under {tool} exited with {server.process.returncode}:\n{server.output()}")
    return out


# strace stops the server at every system call, which changes the timing and so what the
# server finds: a speculative read that would find nothing at full speed may find the next
# request under strace. perf's tracepoints count without stopping it, so when perf works
# the runner counts both ways.
PERF_SYSCALLS = ("recvfrom", "sendto", "recvmsg", "sendmsg", "read", "write", "epoll_wait", "epoll_ctl",
                 "pselect6", "select", "timerfd_settime")
PERF_EVENTS = ["raw_syscalls:sys_enter"] + [f"syscalls:sys_enter_{name}" for name in PERF_SYSCALLS]


def perf_usable() -> bool:
    if not shutil.which("perf"):
        return False
    try:
        probe = subprocess.run(["perf", "stat", "-x,", "-e", ",".join(PERF_EVENTS), "--", "true"],
                               capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return probe.returncode == 0 and "not supported" not in probe.stderr


def perf_counts(server: Server, tools: Tools, settings: Settings, requests: int, out: Path) -> dict[str, int]:
    """System calls of the running server while the load makes `requests` requests."""
    perf = subprocess.Popen(["perf", "stat", "-x,", "-I", "100", "-o", str(out), "-e", ",".join(PERF_EVENTS),
                             "-p", str(server.pid)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 10
        while not (out.exists() and "sys_enter" in out.read_text()):  # the first interval: counting
            if time.monotonic() > deadline or perf.poll() is not None:
                raise BenchError("perf stat did not start counting")
            time.sleep(0.05)
        run_load(tools, server.modbus_port, settings.exact_connections, 1, requests=requests)
    finally:
        perf.send_signal(signal.SIGINT)
        perf.wait(timeout=30)
    counts: dict[str, int] = {}
    for line in out.read_text().splitlines():
        fields = line.split(",")
        if line.startswith("#") or len(fields) < 4 or not fields[1].isdigit():
            continue
        name = fields[3].split(":")[-1].removeprefix("sys_enter_").replace("sys_enter", "total")
        counts[name] = counts.get(name, 0) + int(fields[1])
    if "total" not in counts:
        raise BenchError(f"no counts in {out}")
    return counts


def per_request(a: dict[str, int], b: dict[str, int], requests: int) -> tuple[float, dict[str, float]]:
    per_call = {name: (b.get(name, 0) - a.get(name, 0)) / requests for name in set(a) | set(b)}
    total = per_call.pop("total")
    return total, {k: round(v, 3) for k, v in sorted(per_call.items(), key=lambda kv: -kv[1]) if abs(v) >= 0.005}


def exact_counts(kinds: list[ServerKind], tools: Tools, workdir: Path, settings: Settings) -> dict:
    small, large = settings.exact_requests
    results: dict[str, dict] = {}
    use_perf = settings.strace and perf_usable()
    for kind in kinds:
        progress(f"exact counts of {kind.name} ({'perf, ' if use_perf else ''}"
                 f"{'strace, ' if settings.strace else ''}{'callgrind' if settings.callgrind else ''})")
        entry: dict = {}
        if use_perf:
            server = Server(kind, tools, workdir)
            try:
                a = perf_counts(server, tools, settings, small, workdir / f"perf-{kind.name}-{small}.csv")
                b = perf_counts(server, tools, settings, large, workdir / f"perf-{kind.name}-{large}.csv")
            finally:
                server.stop()
            entry["perf_syscalls_per_request"], entry["perf_syscalls_by_name"] = per_request(a, b, large - small)
        if settings.strace:
            a = strace_counts(exact_run(kind, tools, workdir, settings, "strace", small))
            b = strace_counts(exact_run(kind, tools, workdir, settings, "strace", large))
            entry["syscalls_per_request"], entry["syscalls_by_name"] = per_request(a, b, large - small)
        if settings.callgrind:
            a = callgrind_instructions(exact_run(kind, tools, workdir, settings, "callgrind", small))
            b = callgrind_instructions(exact_run(kind, tools, workdir, settings, "callgrind", large))
            entry["instructions_per_request"] = (b - a) / (large - small)
        results[kind.name] = entry
        progress(f"exact counts of {kind.name}: {entry}")
    return results


# --- propagation ------------------------------------------------------------------------

def propagation(kind: ServerKind, tools: Tools, workdir: Path, settings: Settings) -> dict:
    server = Server(kind, tools, workdir)
    try:
        command = [tools.propagation, "--modbus-port", str(server.modbus_port), "--feed-port", str(server.feed_port),
                   "--changes", str(settings.changes), "--warmup", str(min(100, settings.changes)),
                   "--read-address", hex(READ_ADDRESS + 1), "--offset", "1", "--write-address", "0x3000",
                   "--w-offset", "0", "--json"]
        result = subprocess.run(command, capture_output=True, text=True, timeout=600)
        if result.returncode != 0:
            raise BenchError(f"propagation probe failed: {result.stderr.strip()}")
        return json.loads(result.stdout)
    finally:
        server.stop()


# --- report -----------------------------------------------------------------------------

def progress(message: str) -> None:
    print(f"  .. {message}", file=sys.stderr, flush=True)


def machine() -> dict:
    model = "?"
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            model = line.split(":", 1)[1].strip()
            break
    return {"cpu": model, "cpus": os.cpu_count(), "kernel": platform.release(),
            "loadavg": Path("/proc/loadavg").read_text().split()[:3]}


def build_type(binary: str) -> str:
    for parent in Path(binary).resolve().parents:
        cache = parent / "CMakeCache.txt"
        if cache.exists():
            match = re.search(r"^CMAKE_BUILD_TYPE:\w+=(.*)$", cache.read_text(), re.M)
            return match.group(1) if match else "?"
    return "?"


def print_report(results: dict, kinds: list[ServerKind], settings: Settings) -> None:
    reference, bridge = kinds[0].name, kinds[1].name
    cells = results["cells"]
    m = results["machine"]
    print(f"\nmachine: {m['cpu']}, {m['cpus']} CPUs, Linux {m['kernel']}, load average {' '.join(m['loadavg'])}; "
          f"build {results['build_type']}")
    print(f"load: function 4, {READ_COUNT} registers at 0x{READ_ADDRESS:04X}; {settings.rounds} rounds of "
          f"{settings.duration} s (+{settings.warmup} s warm-up) per server, alternating; medians; "
          f"CPU placement: {settings.pin}\n")
    header = (f"{'depth':>5} {'conn':>4}  {'server':<26} {'req/s':>9} {'p50 µs':>8} {'p99 µs':>8} {'p99.9 µs':>9} "
              f"{'CPU µs/req':>10}  {'ratio req/s':>11} {'ratio p99':>9}")
    print(header)
    print("-" * len(header))
    for depth in settings.depths:
        for connections in settings.connections:
            for kind in kinds:
                cell = cells[(depth, connections, kind.name)]
                ratio = "" if kind.reference else (
                    f"{ratios(cells, depth, connections, kind.name, reference, 'rps'):>11.2f} "
                    f"{ratios(cells, depth, connections, kind.name, reference, 'p99_us'):>9.2f}")
                if kind.name != bridge and not kind.reference:  # another config: its cost over the plain one
                    per_round = round_ratios(cells, depth, connections, kind.name, bridge, 'rps')
                    ratio += (f"   vs {bridge}: req/s {statistics.median(per_round):.2f}{quartiles(per_round)}"
                              f", p99 {ratios(cells, depth, connections, kind.name, bridge, 'p99_us'):.2f}")
                if "monitor_dropped" in cell.runs[0]:
                    ratio += f", monitor lines dropped {sum(run['monitor_dropped'] for run in cell.runs)}"
                print(f"{depth:>5} {connections:>4}  {kind.name:<26} {cell.median('rps'):>9.0f} "
                      f"{cell.median('p50_us'):>8.1f} {cell.median('p99_us'):>8.1f} {cell.median('p999_us'):>9.1f} "
                      f"{cell.median('cpu_us_per_request'):>10.2f}  {ratio}")
    clients = max(settings.connections)
    print(f"\n{'server':<26} {'syscalls/req':>12} {'(perf)':>7} {'instr/req':>10} {'peak RSS':>10} "
          f"{'idle: CPU, wake-ups':>20} {f'{clients} idle clients: CPU, wake-ups':>32}")
    for kind in kinds:
        exact = results["exact"].get(kind.name, {})
        res = results["resources"][kind.name]
        syscalls = f"{exact['syscalls_per_request']:.2f}" if "syscalls_per_request" in exact else "-"
        perf = f"{exact['perf_syscalls_per_request']:.2f}" if "perf_syscalls_per_request" in exact else "-"
        instructions = f"{exact['instructions_per_request']:.0f}" if "instructions_per_request" in exact else "-"
        print(f"{kind.name:<26} {syscalls:>12} {perf:>7} {instructions:>10} {res['peak_rss_kib'] / 1024:>6.1f} MiB "
              f"{res['idle_cpu_ms']:>6.0f} ms, {res['idle_wakeups']:>2} in {res['idle_seconds']:g} s "
              f"{res['idle_clients_cpu_ms']:>18.0f} ms, {res['idle_clients_wakeups']:>2} in {res['idle_seconds']:g} s")
    print(f"\nsystem calls per request by name, {settings.exact_connections} connections, depth 1:")
    for kind in kinds:
        exact = results["exact"].get(kind.name, {})
        for method, key in (("strace -c", "syscalls_by_name"), ("perf stat", "perf_syscalls_by_name")):
            if key in exact:
                print(f"  {kind.name:<26} {method:<10} " + " ".join(f"{k} {v:g}" for k, v in exact[key].items()))
    for name, p in results["propagation"].items():
        print(f"\npropagation ({name}, {p['changes']} changes): feed -> Modbus p50 {p['feed_to_modbus']['p50_us']:.0f} µs, "
              f"p99 {p['feed_to_modbus']['p99_us']:.0f} µs; Modbus -> feed p50 {p['modbus_to_feed']['p50_us']:.0f} µs, "
              f"p99 {p['modbus_to_feed']['p99_us']:.0f} µs (one read round trip: p50 "
              f"{p['read_round_trip']['p50_us']:.0f} µs)")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build-dir", default=str(SOURCE_DIR / "build-release"),
                        help="where the built programs are (default: build-release)")
    parser.add_argument("--bridged"), parser.add_argument("--load")
    parser.add_argument("--reference"), parser.add_argument("--propagation")
    parser.add_argument("--bridge-config", action="append", default=[], metavar="YAML",
                        help="another bridge config to measure beside bench/configs/bridge.yaml (repeatable); "
                             "@MODBUS_PORT@, @FEED_PORT@ and @DIR@ are filled in")
    parser.add_argument("--other-bridged", metavar="BINARY",
                        help="another build of unima-bridged (a change's parent, say), run with the same "
                             "bridge configs in the same rounds; its rows are named other:CONFIG and compared "
                             "with this build's plain daemon")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--duration", type=float, default=2.0, help="seconds per run")
    parser.add_argument("--warmup", type=float, default=0.3, help="seconds per run not measured")
    parser.add_argument("--connections", default="1,8,64")
    parser.add_argument("--depths", default="1,8", help="pipelining depths")
    parser.add_argument("--exact-connections", type=int, default=64)
    parser.add_argument("--exact-requests", default="20000,60000",
                        help="the two request counts whose difference the exact counts use")
    parser.add_argument("--changes", type=int, default=10000, help="changes each way for the propagation")
    parser.add_argument("--idle", type=float, default=3.0, help="seconds of the idle check")
    parser.add_argument("--pin", choices=("none", "apart", "same"), default="none",
                        help="throughput runs: leave placement to the scheduler, or pin the server to CPU 0 and "
                             "the load to CPU 1 (apart) or to CPU 0 too (same)")
    parser.add_argument("--no-callgrind", action="store_true")
    parser.add_argument("--no-strace", action="store_true")
    parser.add_argument("--quick", action="store_true", help="a short run of everything (the CTest `bench` test)")
    parser.add_argument("--json", metavar="FILE", help="also write every figure to FILE")
    args = parser.parse_args()

    build = Path(args.build_dir)
    tools = Tools(args.bridged or str(build / "bin/unima-bridged"),
                  args.load or str(build / "bench/unima-bench-load"),
                  args.reference or str(build / "bench/unima-bench-libmodbus-server"),
                  args.propagation or str(build / "bench/unima-bench-propagation"))
    for path in vars(tools).values():
        if not os.access(path, os.X_OK):
            print(f"run_bench: {path} is not built (cmake --build {build})", file=sys.stderr)
            return 1
    if args.quick:
        settings = Settings(rounds=1, duration=0.3, warmup=0.05, connections=[1, 8, 64], depths=[1, 8],
                            exact_connections=16, exact_requests=(200, 600), idle_seconds=0.3, changes=200,
                            callgrind=not args.no_callgrind, strace=not args.no_strace, pin=args.pin)
    else:
        small, large = (int(n) for n in args.exact_requests.split(","))
        settings = Settings(rounds=args.rounds, duration=args.duration, warmup=args.warmup,
                            connections=[int(n) for n in args.connections.split(",")],
                            depths=[int(n) for n in args.depths.split(",")],
                            exact_connections=args.exact_connections, exact_requests=(small, large),
                            idle_seconds=args.idle, changes=args.changes,
                            callgrind=not args.no_callgrind, strace=not args.no_strace, pin=args.pin)
    for tool, wanted in (("strace", settings.strace), ("valgrind", settings.callgrind)):
        if wanted and not shutil.which(tool):
            print(f"run_bench: {tool} is not installed (scripts/install-deps.sh installs it)", file=sys.stderr)
            return 1

    kinds = [ServerKind("libmodbus", reference=True), ServerKind("unima-bridged", config_template=BENCH_DIR / "configs/bridge.yaml")]
    for config in args.bridge_config:
        kinds.append(ServerKind(f"unima-bridged:{Path(config).stem}", config_template=Path(config).resolve()))
    if args.other_bridged:
        other = str(Path(args.other_bridged).resolve())
        for config in [BENCH_DIR / "configs/bridge.yaml", *args.bridge_config]:
            kinds.append(ServerKind(f"other:{Path(config).stem}", config_template=Path(config).resolve(), binary=other))

    results: dict = {"machine": machine(), "build_type": build_type(tools.bridged)}
    failed = False
    with tempfile.TemporaryDirectory(prefix="unima-bench-") as tmp:
        workdir = Path(tmp)
        for kind in kinds[2:]:  # a config this daemon cannot run is reported, and the rest measured
            try:
                Server(kind, tools, workdir).stop()
            except BenchError as e:
                print(f"run_bench: {kind.name} left out: {e}", file=sys.stderr)
                kinds.remove(kind)
                failed = True
        try:
            results["cells"], results["resources"] = throughput(kinds, tools, workdir, settings)
            results["exact"] = exact_counts(kinds, tools, workdir, settings)
            results["propagation"] = {k.name: propagation(k, tools, workdir, settings) for k in kinds if not k.reference}
        except (BenchError, subprocess.TimeoutExpired) as e:
            print(f"run_bench: {e}", file=sys.stderr)
            return 1
    print_report(results, kinds, settings)
    if args.json:
        serialisable = dict(results)
        serialisable["cells"] = {f"depth {d} conn {c} {n}": cell.runs for (d, c, n), cell in results["cells"].items()}
        Path(args.json).write_text(json.dumps(serialisable, indent=1))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
