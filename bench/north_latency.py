#!/usr/bin/env python3
"""How soon a single change reaches the north (issue 32's propagation target,
docs/performance.md "MQTT" and "HTTP"): a fed telegram that changes D1's engine_speed
after a quiet moment (every 120-220 ms, at random), among 1,000 telegrams a second that
repeat D1's other values, until a mosquitto_sub subscriber has the D1 document that
carries it and a page listening to /api/events has the `values` event that does.
One daemon per --bridged binary, all running side by side (each with MQTT and HTTP); the
rounds go through them in an order that alternates, each round --seconds of feed to one
daemon while the others idle. Prints one JSON line per binary: the medians over rounds of
each round's p50 and p99 (ms), and the samples.
Usage: bench/north_latency.py --bridged A [--bridged B] [--rounds 5] [--seconds 10]
"""
import argparse
import json
import os
import random
import shutil
import socket
import statistics
import subprocess
import tempfile
import threading
import time


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_port(port, what):
    for _ in range(200):
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
            return
        except OSError:
            time.sleep(0.05)
    raise SystemExit(f"{what} did not start")


class Daemon:
    def __init__(self, index, bridged, work, broker):
        self.modbus, self.feed, self.http = free_port(), free_port(), free_port()
        self.topic = f"bench/edge{index}"
        config = os.path.join(work, f"d{index}.yaml")
        with open(config, "w") as f:
            f.write(f"unimabus: {{ transport: feed, listen: 127.0.0.1:{self.feed} }}\n"
                    f"modbus: {{ tcp: {{ listen: 127.0.0.1, port: {self.modbus} }} }}\n"
                    "banks: { D1: 0x1100 }\n"
                    "devices: { D1: { type: unigen-chp, address: 5 } }\n"
                    "log: { level: warn }\n"
                    f"status: {{ socket: {work}/d{index}.sock }}\n"
                    "state: { file: none }\n"
                    f"http: {{ listen: 127.0.0.1, port: {self.http} }}\n"
                    f"mqtt: {{ broker: 'mqtt://127.0.0.1:{broker}', client_id: edge{index}, topic: {self.topic}, "
                    "buffer: { file: none } }\n")
        self.log = open(os.path.join(work, f"d{index}.log"), "w")
        self.process = subprocess.Popen([bridged, "--config", config], stdout=self.log, stderr=subprocess.STDOUT)
        wait_port(self.modbus, bridged)
        wait_port(self.http, bridged)


def page_reader(port, arrivals, stop):
    """arrivals[speed] = when the page first had a values event carrying it."""
    page = socket.create_connection(("127.0.0.1", port))
    page.sendall(b"GET /api/events HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept: text/event-stream\r\n\r\n")
    page.settimeout(0.2)
    buffered = b""
    while not stop.is_set():
        try:
            chunk = page.recv(65536)
        except socket.timeout:
            continue
        if not chunk:
            break
        now = time.time()
        buffered += chunk
        *events, buffered = buffered.split(b"\n\n")
        for event in events:
            if not event.startswith(b"event: values\n"):
                continue
            data = json.loads(event.split(b"data: ", 1)[1])
            speed = data.get("D1/engine_speed", {}).get("value")
            if speed is not None and speed not in arrivals:
                arrivals[speed] = now
    page.close()


def round_of(daemon, broker, seconds, rng):
    """One round: returns (mqtt latencies, page latencies) in ms."""
    # To a file, not a pipe: documents of a few kB fill a pipe that nobody reads until the
    # end, and a subscriber blocked on it takes no more.
    received = tempfile.TemporaryFile("w+")
    subscriber = subprocess.Popen(["mosquitto_sub", "-p", str(broker), "-t", daemon.topic + "/D1", "-F", "%U %p"],
                                  stdout=received, text=True)
    page_arrivals, stop = {}, threading.Event()
    reader = threading.Thread(target=page_reader, args=(daemon.http, page_arrivals, stop))
    reader.start()
    time.sleep(0.5)
    feed = socket.create_connection(("127.0.0.1", daemon.feed))
    feed.setblocking(False)
    values = [(i * 13) % 1000 for i in range(64)]
    base = rng.randrange(1, 20000)
    sent_at, speed = {}, base
    start = paced_from = time.monotonic()
    next_change = start + 0.3
    sequence = 0
    while time.monotonic() - start < seconds:
        lines = []
        for _ in range(10):  # 10 telegrams every 10 ms: 1,000 a second
            sequence += 1
            change = time.monotonic() >= next_change
            if change:
                speed += 1
                next_change = time.monotonic() + rng.uniform(0.12, 0.22)
            values[1] = speed
            lines.append(json.dumps({"addr": 5, "slot": 0, "offset": 0, "values": values}) + "\n")
            if change:
                data = "".join(lines).encode()
                lines = []
                while data:
                    try:
                        data = data[feed.send(data):]
                    except BlockingIOError:
                        time.sleep(0.0005)
                sent_at[speed] = time.time()
        data = "".join(lines).encode()
        while data:
            try:
                data = data[feed.send(data):]
            except BlockingIOError:
                time.sleep(0.0005)
        try:
            while feed.recv(65536):
                pass
        except BlockingIOError:
            pass
        delay = paced_from + sequence / 1000 - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        elif delay < -0.05:  # a feeder that fell behind goes on from now, not in a burst
            paced_from -= delay
    time.sleep(0.5)
    feed.close()
    stop.set()
    reader.join()
    subscriber.terminate()
    subscriber.wait()
    received.seek(0)
    output = received.read()
    mqtt_arrivals = {}
    for line in output.splitlines():
        stamp, _, payload = line.partition(" ")
        try:
            got = json.loads(payload).get("engine_speed")
        except (ValueError, AttributeError):
            continue
        if got is not None and got not in mqtt_arrivals:
            mqtt_arrivals[got] = float(stamp)
    # A retained document or a page's first picture from an earlier round is not an arrival.
    mqtt = [(mqtt_arrivals[s] - t) * 1000 for s, t in sent_at.items() if mqtt_arrivals.get(s, 0) >= t]
    page = [(page_arrivals[s] - t) * 1000 for s, t in sent_at.items() if page_arrivals.get(s, 0) >= t]
    return mqtt, page, len(sent_at)


def p(samples, q):
    if len(samples) < 2:
        return None
    return statistics.quantiles(samples, n=100)[q - 1] if q != 50 else statistics.median(samples)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--bridged", action="append", required=True)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--seconds", type=float, default=10)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    work = tempfile.mkdtemp()
    broker = free_port()
    with open(os.path.join(work, "broker.conf"), "w") as f:
        f.write(f"listener {broker} 127.0.0.1\nallow_anonymous true\npersistence false\nlog_dest none\n")
    processes = [subprocess.Popen(["mosquitto", "-c", os.path.join(work, "broker.conf")], stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)]
    try:
        wait_port(broker, "mosquitto")
        daemons = [Daemon(i, b, work, broker) for i, b in enumerate(args.bridged)]
        processes += [d.process for d in daemons]
        time.sleep(1)
        results = [{"mqtt_p50": [], "mqtt_p99": [], "page_p50": [], "page_p99": [], "changes": 0, "mqtt_seen": 0,
                    "page_seen": 0} for _ in daemons]
        for r in range(args.rounds):
            order = list(range(len(daemons)))
            if r % 2:
                order.reverse()
            for i in order:
                mqtt, page, changes = round_of(daemons[i], broker, args.seconds, rng)
                result = results[i]
                result["changes"] += changes
                result["mqtt_seen"] += len(mqtt)
                result["page_seen"] += len(page)
                for name, samples in (("mqtt", mqtt), ("page", page)):
                    for q in (50, 99):
                        value = p(samples, q)
                        if value is not None:
                            result[f"{name}_p{q}"].append(value)
        for bridged, result in zip(args.bridged, results):
            summary = {"bridged": bridged, "rounds": args.rounds, "changes": result["changes"],
                       "mqtt_seen": result["mqtt_seen"], "page_seen": result["page_seen"]}
            for key in ("mqtt_p50", "mqtt_p99", "page_p50", "page_p99"):
                rounds = result[key]
                summary[key] = round(statistics.median(rounds), 1) if rounds else None
                summary[key + "_rounds"] = [round(x, 1) for x in rounds]
            print(json.dumps(summary))
    finally:
        for process in processes:
            process.terminate()
        for process in processes:
            process.wait()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
