#!/usr/bin/env python3
"""The plant side of bench/mqtt.sh: a feed driver (docs/feed.md) that changes every
register of D1 (UnimaBUS address 5, 64 registers) --rate times a second for --seconds,
engine_speed (offset 1) counting telegrams. With --broker and --topic it also listens to
the bank's documents (mosquitto_sub) and reports how long a fed value took to reach a
subscriber: {"telegrams":…,"p50_ms":…,"p99_ms":…,"documents":…}.
"""
import argparse
import json
import socket
import statistics
import subprocess
import tempfile
import time


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--feed-port", type=int, required=True)
    parser.add_argument("--rate", type=float, default=1000)
    parser.add_argument("--seconds", type=float, default=5)
    parser.add_argument("--broker", type=int)
    parser.add_argument("--topic")
    args = parser.parse_args()

    listener = None
    if args.broker:
        # To a file, not a pipe: a document is a few kB, and a subscriber blocked on a full
        # pipe that is read only at the end takes no more (the count was ~9 documents).
        received = tempfile.TemporaryFile("w+")
        listener = subprocess.Popen(["mosquitto_sub", "-p", str(args.broker), "-t", args.topic, "-F", "%U %p"],
                                    stdout=received, text=True)
        time.sleep(0.3)
    feed = socket.create_connection(("127.0.0.1", args.feed_port))
    feed.setblocking(False)
    sent_at = {}
    start = time.monotonic()
    paced_from = start  # moves on after a pause, so that the rate is kept, never made up in a burst
    sequence = 0
    batch = max(1, int(args.rate / 100))  # every 10 ms
    while time.monotonic() - start < args.seconds:
        lines = []
        for _ in range(batch):
            sequence += 1
            speed = 1 + sequence % 30000
            values = [(sequence * 7 + i * 13) % 1000 for i in range(64)]
            values[1] = speed
            lines.append(json.dumps({"addr": 5, "slot": 0, "offset": 0, "values": values}) + "\n")
            sent_at[speed] = time.time()
        data = "".join(lines).encode()
        while data:
            try:
                data = data[feed.send(data):]
            except BlockingIOError:
                time.sleep(0.001)
        try:
            while feed.recv(65536):  # what the bridge sends its drivers (the snapshot, writes)
                pass
        except BlockingIOError:
            pass
        next_batch = paced_from + sequence / args.rate
        behind = time.monotonic() - next_batch
        if behind > 0.1:  # stopped a while (bench/all_features.py stops the feeders it does not measure)
            paced_from += behind
            next_batch += behind
        delay = next_batch - time.monotonic()
        if delay > 0:
            time.sleep(delay)
    elapsed = time.monotonic() - start
    result = {"telegrams": sequence, "per_second": round(sequence / elapsed)}
    if listener:
        time.sleep(0.5)
        listener.terminate()
        listener.wait()
        received.seek(0)
        output = received.read()
        latencies = []
        for line in output.splitlines():
            stamp, _, payload = line.partition(" ")
            try:
                speed = json.loads(payload).get("engine_speed")
            except (ValueError, AttributeError):
                continue  # an empty retained clear, or the last line cut by terminate()
            if speed in sent_at:
                latencies.append((float(stamp) - sent_at[speed]) * 1000)
        result["documents"] = len(latencies)
        if len(latencies) >= 2:
            q = statistics.quantiles(latencies, n=100)
            result["p50_ms"] = round(statistics.median(latencies), 1)
            result["p99_ms"] = round(q[98], 1)
    print(json.dumps(result))


if __name__ == "__main__":
    main()
