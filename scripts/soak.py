#!/usr/bin/env python3
"""The soak and fault harness of issue 17 (docs/operations.md, "Soak and faults").

Runs the real daemon, over loopback only, through what a plant's years bring:

  steady      CLIENTS Modbus TCP clients reading flat out for MINUTES, a feed driver
              sending telegrams, a writer changing W, the monitor file on; the daemon's
              resident set and descriptors sampled, their drift reported
  kill9       the daemon killed with SIGKILL at random instants during a write stream,
              ROUNDS times: every acknowledged value must be back after the restart
  reloads     a storm of SIGHUPs under load, good and broken configs in turn
  feed-kill   feed drivers killed in the middle of a line, one after another
  full-disk   the monitor file on a file system that fills up, then gets room again

Each phase ends with a verdict; the exit status is 0 only when every phase held.
Nothing here is part of CI (it takes minutes); scripts/soak.sh builds and runs it.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import resource
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

W_BASE = 0x3000
D1_BASE = 0x1100


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class ModbusClient:
    """The few Modbus TCP calls the harness needs; raises OSError when the daemon is gone."""

    def __init__(self, port: int, timeout: float = 3.0):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=timeout)
        self.transaction = 0

    def close(self) -> None:
        self.sock.close()

    def _call(self, pdu: bytes) -> bytes:
        self.transaction = (self.transaction + 1) & 0xFFFF
        self.sock.sendall(struct.pack(">HHHB", self.transaction, 0, len(pdu) + 1, 1) + pdu)
        header = self._exactly(7)
        transaction, _, length, _ = struct.unpack(">HHHB", header)
        body = self._exactly(length - 1)
        if transaction != self.transaction:
            raise OSError(f"answer to transaction {transaction}, expected {self.transaction}")
        if body[0] & 0x80:
            raise OSError(f"exception {body[1]:02X} to function {body[0] & 0x7F}")
        return body

    def _exactly(self, n: int) -> bytes:
        data = b""
        while len(data) < n:
            chunk = self.sock.recv(n - len(data))
            if not chunk:
                raise OSError("connection closed")
            data += chunk
        return data

    def write(self, address: int, value: int) -> None:
        self._call(struct.pack(">BHH", 6, address, value))

    def write_many(self, address: int, values: list[int]) -> None:
        self._call(struct.pack(">BHHB", 16, address, len(values), 2 * len(values)) + struct.pack(f">{len(values)}H", *values))

    def read_holding(self, address: int, count: int) -> list[int]:
        body = self._call(struct.pack(">BHH", 3, address, count))
        return list(struct.unpack(f">{count}H", body[2:]))

    def read_input(self, address: int, count: int) -> list[int]:
        body = self._call(struct.pack(">BHH", 4, address, count))
        return list(struct.unpack(f">{count}H", body[2:]))


class Daemon:
    def __init__(self, binary: Path, work: Path, monitor_dir: Path | None = None, state: bool = True,
                 max_clients: int = 600):
        self.binary, self.work = binary, work
        self.modbus_port, self.feed_port = free_port(), free_port()
        self.config = work / "bridge.yaml"
        self.log_path = work / "daemon.log"
        self.monitor_dir = monitor_dir or work
        self.state = state
        self.max_clients = max_clients
        self.process: subprocess.Popen | None = None
        self.write_config()

    def config_text(self, broken: bool = False, variant: int = 0) -> str:
        text = f"""unimabus:
  address: 5
  transport: feed
  listen: 127.0.0.1:{self.feed_port}
  offline_after: {5 + variant % 3}s
modbus:
  address: 1
  tcp: {{ listen: 127.0.0.1, port: {self.modbus_port}, max_clients: {self.max_clients} }}
banks: {{ D1: {D1_BASE:#06x}, W: {W_BASE:#06x} }}
devices:
  D1: {{ type: unigen-chp, address: 5 }}
monitor:
  file: {self.monitor_dir / 'monitor.log'}
  max_size: 1MB
  max_files: 3
log: {{ level: {'info' if variant % 2 == 0 else 'warn'} }}
status: {{ socket: {self.work / 'control.sock'} }}
state: {{ file: {self.work / 'bridge.state' if self.state else 'none'} }}
"""
        return text.replace("max_clients:", "max_clients: [") if broken else text

    def write_config(self, broken: bool = False, variant: int = 0) -> None:
        tmp = self.config.with_suffix(".tmp")
        tmp.write_text(self.config_text(broken, variant))
        tmp.replace(self.config)

    def start(self) -> None:
        log = open(self.log_path, "ab")
        self.process = subprocess.Popen([str(self.binary), "--config", str(self.config)], stdout=log, stderr=log)
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            try:
                socket.create_connection(("127.0.0.1", self.modbus_port), timeout=0.2).close()
                return
            except OSError:
                if self.process.poll() is not None:
                    break
                time.sleep(0.05)
        raise RuntimeError("the daemon did not start:\n" + self.log_path.read_text()[-3000:])

    @property
    def pid(self) -> int:
        return self.process.pid

    def alive(self) -> bool:
        return self.process is not None and self.process.poll() is None

    def rss_kib(self) -> int:
        for line in Path(f"/proc/{self.pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
        return 0

    def descriptors(self) -> int:
        return len(os.listdir(f"/proc/{self.pid}/fd"))

    def kill9(self) -> None:
        self.process.kill()
        self.process.wait()

    def stop(self) -> None:
        if self.alive():
            self.process.terminate()
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.kill9()

    def log_count(self, text: str) -> int:
        return self.log_path.read_text(errors="replace").count(text)


class FeedDriver(threading.Thread):
    """A UnimaBUS driver on the feed: `rate` telegrams a second for D1, reading what comes back."""

    def __init__(self, port: int, rate: float):
        super().__init__(daemon=True)
        self.port, self.rate = port, rate
        self.stopping = threading.Event()
        self.sent = 0
        self.errors: list[str] = []

    def run(self) -> None:
        try:
            sock = socket.create_connection(("127.0.0.1", self.port), timeout=5)
            threading.Thread(target=self._drain, args=(sock,), daemon=True).start()
            value = 0
            while not self.stopping.is_set():
                value = (value + 1) % 30000
                line = json.dumps({"addr": 5, "slot": 0, "offset": value % 40, "values": [value]}) + "\n"
                sock.sendall(line.encode())
                self.sent += 1
                time.sleep(1 / self.rate)
            sock.close()
        except OSError as e:
            self.errors.append(str(e))

    @staticmethod
    def _drain(sock: socket.socket) -> None:
        try:
            while sock.recv(65536):
                pass
        except OSError:
            pass

    def stop(self) -> None:
        self.stopping.set()
        self.join(5)


class Load:
    """unima-bench-load in the background: `connections` clients reading D1 flat out."""

    def __init__(self, binary: Path, port: int, connections: int, seconds: float, function: int = 4):
        self.process = subprocess.Popen(
            [str(binary), "--port", str(port), "--connections", str(connections), "--function", str(function),
             "--address", str(D1_BASE), "--quantity", "64", "--duration", str(seconds), "--json"],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def result(self, timeout: float) -> dict:
        out, err = self.process.communicate(timeout=timeout)
        if self.process.returncode != 0:
            return {"error": err.strip() or f"exit {self.process.returncode}"}
        return json.loads(out)


def mib(kib: float) -> str:
    return f"{kib / 1024:.1f} MiB"


class Harness:
    def __init__(self, args: argparse.Namespace):
        self.args = args
        build = Path(args.build)
        self.bridged = build / "bin" / "unima-bridged"
        self.load = next(build.rglob("unima-bench-load"))
        base = Path(args.work) if args.work else None
        self.root = Path(tempfile.mkdtemp(prefix="unima-soak.", dir=base))
        self.verdicts: list[tuple[str, bool, str]] = []

    def verdict(self, phase: str, held: bool, figures: str) -> None:
        self.verdicts.append((phase, held, figures))
        print(f"[{phase}] {'held' if held else 'FAILED'}: {figures}", flush=True)

    def fresh(self, name: str, **options) -> Daemon:
        work = self.root / name
        work.mkdir()
        return Daemon(self.bridged, work, **options)

    # -- steady ---------------------------------------------------------------------------
    def steady(self) -> None:
        minutes, clients = self.args.minutes, self.args.clients
        daemon = self.fresh("steady")
        daemon.start()
        feed = FeedDriver(daemon.feed_port, rate=200)
        feed.start()
        seconds = minutes * 60
        load = Load(self.load, daemon.modbus_port, clients, seconds)
        writer = ModbusClient(daemon.modbus_port)
        samples: list[tuple[float, int, int]] = []
        writes = 0
        start = time.monotonic()
        next_sample = start
        while time.monotonic() - start < seconds and daemon.alive() and load.process.poll() is None:
            writer.write_many(W_BASE, [(writes + i) % 30000 for i in range(16)])
            writes += 1
            if time.monotonic() >= next_sample:
                samples.append((time.monotonic() - start, daemon.rss_kib(), daemon.descriptors()))
                next_sample += self.args.sample
            time.sleep(0.02)
        result = load.result(timeout=seconds + 60)
        writer.close()
        feed.stop()
        time.sleep(1)  # the clients' connections are closed and gone from the daemon
        alive = daemon.alive()
        after = (daemon.rss_kib(), daemon.descriptors()) if alive else (0, 0)
        self.steady_samples = samples
        # The first fifth is the warm-up: buffers and the allocator's pools reach their size.
        settled = [s for s in samples if s[0] >= seconds / 5] or samples
        first, last = settled[0], settled[-1]
        span_min = max((last[0] - first[0]) / 60, 1e-9)
        drift = (last[1] - first[1]) / span_min
        peak = max(s[1] for s in samples)
        fds = sorted({s[2] for s in settled})
        held = (alive and "error" not in result and not feed.errors and last[1] - first[1] <= 2048
                and max(s[2] for s in settled) - min(s[2] for s in settled) <= 8)
        self.verdict("steady", held,
                     f"{minutes} min, {clients} clients: {result.get('rps', 0):.0f} reads/s "
                     f"(p99 {result.get('p99_us', 0) / 1000:.1f} ms){' ' + result['error'] if 'error' in result else ''}, "
                     f"{writes} fn-16 writes, {feed.sent} feed telegrams; RSS {mib(first[1])} after warm-up, "
                     f"{mib(last[1])} at the end (drift {drift:+.0f} KiB/min), peak {mib(peak)}; descriptors "
                     f"{fds[0]}..{fds[-1]} under load, {after[1]} after; RSS after {mib(after[0])}")
        daemon.stop()

    # -- kill9 ----------------------------------------------------------------------------
    def kill9(self) -> None:
        daemon = self.fresh("kill9")
        rounds, lost, acknowledged_total, bad_loads = self.args.rounds, 0, 0, 0
        rng = random.Random(17)
        value = 0
        for _ in range(rounds):
            daemon.start()
            acked: list[int] = []
            stop = threading.Event()

            def write_stream() -> None:
                nonlocal value
                try:
                    client = ModbusClient(daemon.modbus_port)
                    while not stop.is_set():
                        value = value % 60000 + 1
                        # W+0 and W+15 in one fn-16: both or neither may come back.
                        client.write_many(W_BASE, [value] + [0] * 14 + [value])
                        acked.append(value)
                except OSError:
                    pass

            thread = threading.Thread(target=write_stream)
            thread.start()
            time.sleep(rng.uniform(0.05, 0.6))
            daemon.kill9()
            stop.set()
            thread.join()
            acknowledged_total += len(acked)
            daemon.start()
            if daemon.log_count("kept aside"):
                bad_loads += 1
            client = ModbusClient(daemon.modbus_port)
            back = client.read_holding(W_BASE, 16)
            client.close()
            if acked:
                last = acked[-1]
                # The write in flight when the kill came may or may not have been made durable.
                if back[0] != back[15] or back[0] not in (last, last % 60000 + 1):
                    lost += 1
                    print(f"  kill9: acknowledged {last}, read back W+0 {back[0]} W+15 {back[15]}", flush=True)
            daemon.kill9()
        self.verdict("kill9", lost == 0 and bad_loads == 0,
                     f"{rounds} kills during writes, {acknowledged_total} acknowledged fn-16 writes, "
                     f"{lost} lost, {bad_loads} state files set aside")

    # -- reloads --------------------------------------------------------------------------
    def reloads(self) -> None:
        daemon = self.fresh("reloads")
        daemon.start()
        feed = FeedDriver(daemon.feed_port, rate=100)
        feed.start()
        count = self.args.reloads
        load = Load(self.load, daemon.modbus_port, 64, count / 50 + 5)
        time.sleep(1)
        rss_before, fds_before = daemon.rss_kib(), daemon.descriptors()
        for i in range(count):
            daemon.write_config(broken=(i % 3 == 2), variant=i)
            daemon.process.send_signal(signal.SIGHUP)
            time.sleep(0.02)
        daemon.write_config(variant=0)
        daemon.process.send_signal(signal.SIGHUP)
        result = load.result(timeout=count / 50 + 60)
        feed.stop()
        time.sleep(1)
        alive = daemon.alive()
        answering = False
        if alive:
            client = ModbusClient(daemon.modbus_port)
            answering = len(client.read_input(D1_BASE, 64)) == 64
            client.close()
        rss_after, fds_after = (daemon.rss_kib(), daemon.descriptors()) if alive else (0, 0)
        held = alive and answering and "error" not in result and fds_after <= fds_before + 2
        self.verdict("reloads", held,
                     f"{count} SIGHUPs at 50/s, every third config broken, under 64 reading clients "
                     f"({result.get('rps', 0):.0f} reads/s){' ' + result['error'] if 'error' in result else ''}; "
                     f"RSS {mib(rss_before)} -> {mib(rss_after)}, descriptors {fds_before} -> {fds_after}")
        daemon.stop()

    # -- feed-kill ------------------------------------------------------------------------
    def feed_kill(self) -> None:
        daemon = self.fresh("feed-kill")
        daemon.start()
        time.sleep(0.5)
        fds_before = daemon.descriptors()
        count = self.args.feed_kills
        half_line = '{"addr":5,"slot":0,"offset":3,"values":[12'
        for _ in range(count):
            child = subprocess.Popen(
                [sys.executable, "-c",
                 "import socket,sys,time\n"
                 f"s=socket.create_connection(('127.0.0.1',{daemon.feed_port}))\n"
                 f"s.sendall({half_line!r}.encode())\n"
                 "print('sent',flush=True)\n"
                 "time.sleep(60)\n"],
                stdout=subprocess.PIPE, text=True)
            child.stdout.readline()
            child.kill()
            child.wait()
        time.sleep(0.5)
        fds_after = daemon.descriptors()
        feed = socket.create_connection(("127.0.0.1", daemon.feed_port))
        feed.sendall(b'{"addr":5,"slot":0,"offset":3,"values":[4321]}\n')
        client = ModbusClient(daemon.modbus_port)
        deadline = time.monotonic() + 5
        value = None
        while time.monotonic() < deadline:
            value = client.read_input(D1_BASE + 3, 1)[0]
            if value == 4321:
                break
            time.sleep(0.05)
        feed.close()
        client.close()
        held = daemon.alive() and value == 4321 and fds_after <= fds_before
        self.verdict("feed-kill", held,
                     f"{count} feed drivers killed mid-line: descriptors {fds_before} -> {fds_after}, "
                     f"a whole line after them applied: {value == 4321}")
        daemon.stop()

    # -- full-disk ------------------------------------------------------------------------
    def full_disk(self) -> None:
        mount = self.root / "small-fs"
        mount.mkdir()
        mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(mount)],
                                 capture_output=True).returncode == 0
        daemon = self.fresh("full-disk", monitor_dir=mount)
        try:
            daemon.start()
            if not mounted:  # no root: the daemon's file size limit stands in for the disk
                resource.prlimit(daemon.pid, resource.RLIMIT_FSIZE, (1536 * 1024, resource.RLIM_INFINITY))
            fill = Load(self.load, daemon.modbus_port, 8, 8)
            fill_result = fill.result(timeout=60)
            full_errors = daemon.log_count("monitor: cannot write")
            # Room again, more than the rotated files need (3 × 1 MB): the file system grows.
            if mounted:
                subprocess.run(["mount", "-o", "remount,size=16m", str(mount)], check=True)
            else:
                resource.prlimit(daemon.pid, resource.RLIMIT_FSIZE, (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
            again = Load(self.load, daemon.modbus_port, 8, 8)
            again_result = again.result(timeout=60)
            recovered = daemon.log_count("monitor: writing")
            held = (daemon.alive() and "error" not in fill_result and "error" not in again_result
                    and full_errors == 1 and recovered == 1)
            self.verdict("full-disk", held,
                         f"{'a 2 MiB tmpfs, grown to 16 MiB' if mounted else 'RLIMIT_FSIZE 1.5 MiB, then none'}: {fill_result.get('rps', 0):.0f} "
                         f"reads/s while full, {again_result.get('rps', 0):.0f} after; 'cannot write' logged "
                         f"{full_errors}×, recovery logged {recovered}×; "
                         f"{daemon.log_count('monitor:')} monitor lines in the daemon's log in all")
        finally:
            daemon.stop()
            if mounted:
                subprocess.run(["umount", str(mount)])

    def run(self, phases: list[str]) -> int:
        table = {"steady": self.steady, "kill9": self.kill9, "reloads": self.reloads,
                 "feed-kill": self.feed_kill, "full-disk": self.full_disk}
        print(f"soak: working in {self.root}", flush=True)
        try:
            for phase in phases:
                try:
                    table[phase]()
                except Exception as e:  # a phase that breaks is a failed phase, the others still run
                    self.verdict(phase, False, f"{type(e).__name__}: {e}")
        finally:
            if not self.args.keep:
                shutil.rmtree(self.root, ignore_errors=True)
        print("\n| phase | held | figures |\n|---|---|---|")
        for phase, held, figures in self.verdicts:
            print(f"| {phase} | {'yes' if held else '**no**'} | {figures} |")
        return 0 if all(held for _, held, _ in self.verdicts) else 1


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build-release")
    parser.add_argument("--minutes", type=float, default=10)
    parser.add_argument("--clients", type=int, default=500)
    parser.add_argument("--sample", type=float, default=5, help="seconds between samples of RSS and descriptors")
    parser.add_argument("--rounds", type=int, default=50, help="kills of the kill9 phase")
    parser.add_argument("--reloads", type=int, default=1000)
    parser.add_argument("--feed-kills", type=int, default=200)
    parser.add_argument("--work", help="where the daemons' files go (a directory on the disk by default)")
    parser.add_argument("--keep", action="store_true", help="keep the work directory")
    parser.add_argument("phases", nargs="*", default=["steady", "kill9", "reloads", "feed-kill", "full-disk"])
    args = parser.parse_args()
    return Harness(args).run(args.phases)


if __name__ == "__main__":
    sys.exit(main())
