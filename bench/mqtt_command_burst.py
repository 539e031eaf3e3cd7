#!/usr/bin/env python3
"""What a burst of MQTT commands does to Modbus (issue 43, finding 6; docs/performance.md).

One daemon with the state file (every command a durable write) and `mqtt.commands` on a
local mosquitto, logging at info as a site does. A Modbus TCP prober reads W3 once every
5 ms on one connection and times each answer. Each round: --idle seconds of the prober
alone, then the same while mosquitto_pub publishes --commands `set/W/3` at QoS 0 as fast
as it can (-l, from a file), until the subscriber (QoS 1) has every answer on
`set/result` (or --limit seconds): the burst is its commands and their answers. The broker
(all_features' own) gets room to queue the whole burst for the bridge. Reports per round the
prober's p50 / p99 / max idle and during the burst, the p99 ratio, when the last value was
read and the last answer came, the daemon's log lines and CPU time, and the host's load
average (the box is shared: say it).
--pin puts the daemon and the prober on CPU 0 and the broker, the publisher and the
subscriber on CPU 1, as at a site whose broker and fleet are other machines: what is left
is the daemon's own turns, not four processes' share of two cores.
The issue's target: during 50,000 commands, max <= 50 ms and p99 <= 2 x idle.
A read that waits --limit seconds stops that round's prober (a_read_waited_the_whole_limit).
Usage: bench/mqtt_command_burst.py [--build-dir build] [--rounds 2] [--commands 50000]
       [--idle 3] [--limit 20] [--pin]
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
W3 = 0x0103  # W at 0x0100 (banks below)
TOPIC = "burst/site"


class Prober(threading.Thread):
    """Reads W3 every PROBE_EVERY s: (when sent, latency s, value) for each answer."""

    def __init__(self, port, limit, cpus=None, realtime=False):
        super().__init__()
        self.cpus = cpus
        self.realtime = realtime
        self.client = ModbusClient(port, timeout=limit)
        self.client.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.samples = []
        self.unanswered = False  # a read waited the whole limit: the prober stopped there
        self.stop = threading.Event()

    def read(self):
        sent = time.perf_counter()
        value = self.client.read_holding(W3, 1)[0]
        return sent, time.perf_counter() - sent, value

    def run(self):
        if self.cpus is not None:
            os.sched_setaffinity(0, self.cpus)  # this thread only (Linux)
        if self.realtime:
            # The prober stands for a master on another machine: its own wake-up must not
            # wait for the processes it measures (SCHED_FIFO; this thread only; root).
            try:
                os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(10))
            except PermissionError:
                self.realtime = False
        next_at = time.perf_counter()
        while not self.stop.is_set():
            try:
                self.samples.append(self.read())
            except TimeoutError:
                self.unanswered = True
                return
            next_at = max(next_at + PROBE_EVERY, time.perf_counter())
            time.sleep(max(0.0, next_at - time.perf_counter()))

    def latest(self):
        return self.samples[-1][2] if self.samples else None


def figures(samples):
    ms = sorted(s[1] * 1000 for s in samples)
    if len(ms) < 2:
        return {"reads": len(ms)}
    return {"reads": len(ms), "p50_ms": round(statistics.median(ms), 2),
            "p99_ms": round(statistics.quantiles(ms, n=100, method="inclusive")[98], 2), "max_ms": round(ms[-1], 2)}


class Bench(all_features.Bench):
    """all_features' processes and broker (its subscriber takes bench/# and spBv1.0/#,
    nothing of this bench's topics), one daemon of its own."""

    def __init__(self, args):  # not all_features': no load generator here
        self.args = args
        self.work = Path(tempfile.mkdtemp(prefix="mqtt-burst-"))
        self.processes = []

    def start(self):
        if self.args.pin:  # inherited by the broker and the clients this thread starts
            os.sched_setaffinity(0, {1})
        # Room for the whole burst in the broker's queue for the bridge while it does not
        # read: mosquitto's default (1,000) drops QoS 0 messages past it, and the bench is of
        # the bridge taking every command, not of the broker dropping them.
        self.broker(f"max_queued_messages {2 * self.args.commands}\n")
        self.modbus, feed = free_port(), free_port()
        config = self.work / "bridge.yaml"
        config.write_text(
            f"unimabus: {{ transport: feed, listen: 127.0.0.1:{feed} }}\n"
            f"modbus: {{ tcp: {{ listen: 127.0.0.1, port: {self.modbus} }} }}\n"
            "banks: { D1: 0x1100, W: 0x0100 }\n"
            "devices: { D1: { type: unigen-chp, address: 5 } }\n"
            "log: { level: info }\n"
            f"status: {{ socket: {self.work / 'bridge.sock'} }}\n"
            f"state: {{ file: {self.work / 'bridge.state'} }}\n"
            f"mqtt: {{ broker: 'mqtt://127.0.0.1:{self.broker_port}', client_id: burst, topic: {TOPIC}, commands: true, "
            "buffer: { file: none } }\n")
        self.log = self.work / "bridge.log"
        bridged = Path(self.args.build_dir) / "bin" / "unima-bridged"
        pin = (lambda: os.sched_setaffinity(0, {0})) if self.args.pin else None
        self.daemon = self.spawn([str(bridged), "--config", str(config)], stdout=self.log.open("w"),
                                 stderr=subprocess.STDOUT, preexec_fn=pin)
        wait_for_port(self.modbus, "unima-bridged", self.log)
        deadline = time.monotonic() + 10
        while "mqtt: connected" not in self.log.read_text():
            if time.monotonic() > deadline:
                sys.exit("the daemon did not connect to the broker:\n" + self.log.read_text())
            time.sleep(0.05)
        self.answers_file = self.work / "answers"
        self.answers_read = self.answers_counted = 0
        self.spawn(["mosquitto_sub", "-p", str(self.broker_port), "-q", "1", "-t", f"{TOPIC}/set/result"],
                   stdout=self.answers_file.open("w"))
        time.sleep(0.3)  # subscribed

    def daemon_cpu_s(self):
        """User and system time of all the daemon's threads so far (/proc/PID/stat)."""
        fields = Path(f"/proc/{self.daemon.pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    def answers(self):
        """Lines the subscriber has written so far, counted from where the last call stopped:
        the prober's thread needs the GIL as soon as its answer comes."""
        with self.answers_file.open("rb") as f:
            f.seek(self.answers_read)
            chunk = f.read()
        self.answers_read += len(chunk)
        self.answers_counted += chunk.count(b"\n")
        return self.answers_counted

    def round(self, number):
        prober = Prober(self.modbus, self.args.limit, {0} if self.args.pin else None, True)
        prober.start()
        time.sleep(self.args.idle)
        idle = list(prober.samples)
        values = [(number * 1000 + i) % 65536 for i in range(1, self.args.commands + 1)]
        lines = self.work / "commands"
        lines.write_text("".join(f"{v}\n" for v in values))
        answers_before, log_before = self.answers(), self.log.read_text().count("\n")
        cpu_before = self.daemon_cpu_s()
        began = len(prober.samples)
        start = time.perf_counter()
        with lines.open() as source:
            publisher = subprocess.run(["mosquitto_pub", "-p", str(self.broker_port), "-q", "0", "-t", f"{TOPIC}/set/W/3", "-l"],
                                       stdin=source, timeout=self.args.limit, check=True)
        published = time.perf_counter() - start
        landed = None
        # The subscriber has every answer (or the limit passed): all carried out, none lost.
        while self.answers() - answers_before < len(values) and prober.is_alive() and time.perf_counter() - start < self.args.limit:
            if landed is None and prober.latest() == values[-1]:
                landed = time.perf_counter() - start
            time.sleep(0.01)
        answered = time.perf_counter() - start
        prober.stop.set()
        prober.join()
        if landed is None and prober.latest() == values[-1]:
            landed = answered
        burst = prober.samples[began:]
        result = {
            "round": number + 1,
            "idle": figures(idle),
            "burst": figures(burst),
            "published_s": round(published, 2),
            "last_value_read_s": round(landed, 2) if landed is not None else None,
            "a_read_waited_the_whole_limit": prober.unanswered,
            "answers": self.answers() - answers_before,
            "all_answered_s": round(answered, 2) if self.answers() - answers_before >= len(values) else None,
            "log_lines": self.log.read_text().count("\n") - log_before,
            "daemon_cpu_s": round(self.daemon_cpu_s() - cpu_before, 2),
            "load": round(os.getloadavg()[0], 2),
            "prober_realtime": prober.realtime,
        }
        if "p99_ms" in result["idle"] and "p99_ms" in result["burst"]:
            result["p99_ratio"] = round(result["burst"]["p99_ms"] / result["idle"]["p99_ms"], 2)
        return result


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build-dir", default="build")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--commands", type=int, default=50000)
    parser.add_argument("--idle", type=float, default=3)
    parser.add_argument("--limit", type=float, default=20, help="seconds a burst may take, at most")
    parser.add_argument("--pin", action="store_true", help="the daemon and prober on CPU 0, broker and clients on CPU 1")
    args = parser.parse_args()
    if args.pin and len(os.sched_getaffinity(0)) < 2:
        sys.exit("--pin needs two CPUs")
    bench = Bench(args)
    complete = True
    try:
        bench.start()
        print(f"load average at the start: {os.getloadavg()[0]:.2f}", file=sys.stderr)
        for n in range(args.rounds):
            result = bench.round(n)
            print(json.dumps(result), flush=True)
            complete = complete and result["answers"] == args.commands and not result["a_read_waited_the_whole_limit"]
    finally:
        bench.close()
    # Not a judgement of speed: every command answered and every read answered in time.
    return 0 if complete else 1


if __name__ == "__main__":
    sys.exit(main())
