#!/usr/bin/env python3
"""The host side of bench/sparkplug.sh (issue 33's performance, docs/performance.md).

    sparkplug_probe.py latency --feed-port P --broker B --topic T [--rate 1000] [--seconds 5] [--probe-every 20]
        A feed driver (docs/feed.md) that changes every register of D1 (UnimaBUS address 5)
        --rate times a second, except engine_speed (offset 1), which changes only every
        --probe-every-th telegram: the probe. A subscriber (mosquitto_sub) takes the DDATA on
        T; a probe's latency is from its telegram to the first DDATA that carries its value
        — the wait for the next look included — and the bridge's share of it, to the DDATA's
        timestamp (when the bridge looked). {"telegrams", "probes", "seen", "p50_ms",
        "p99_ms", "max_ms", "bridge_p50_ms", "bridge_p99_ms", "ddata"}
    sparkplug_probe.py births --broker B --group G --node N [--rounds 5]
        Sends NCMD Node Control/Rebirth --rounds times, --spacing seconds apart (5.5 by
        default: the bridge carries out one rebirth per 5 s, sparkplug/rebirth_pacing, and
        one asked sooner goes when the 5 s are up), and measures each
        round's births: the bytes of NBIRTH + every DBIRTH, the devices born, and the time from
        the NCMD leaving this process to the last DBIRTH reaching the subscriber.

Payloads are read with tests/support/sparkplug_decode.py (written from the specification,
not the bridge's code); the NCMD is encoded here by hand from the same field numbers and
sent over a raw MQTT 3.1.1 connection, so that its time is taken as it leaves.
"""
import argparse
import json
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "support"))
import sparkplug_decode  # noqa: E402


def varint(n):
    out = bytearray()
    while True:
        byte = n & 0x7F
        n >>= 7
        out.append(byte | (0x80 if n else 0))
        if not n:
            return bytes(out)


def mqtt_string(text):
    data = text.encode()
    return len(data).to_bytes(2, "big") + data


def mqtt_connect(port, client_id):
    sock = socket.create_connection(("127.0.0.1", port))
    body = mqtt_string("MQTT") + bytes([4, 0x02]) + (60).to_bytes(2, "big") + mqtt_string(client_id)
    sock.sendall(bytes([0x10]) + varint(len(body)) + body)
    connack = sock.recv(4)
    if len(connack) != 4 or connack[0] != 0x20 or connack[3] != 0:
        raise SystemExit(f"the broker refused the connection: {connack!r}")
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock


def mqtt_publish(sock, topic, payload):
    body = mqtt_string(topic) + payload
    sock.sendall(bytes([0x30]) + varint(len(body)) + body)


def rebirth_payload():
    # Sparkplug B Payload.metrics (2) = Metric{name (1), datatype (4) = Boolean (11), boolean_value (14) = true}
    name = b"Node Control/Rebirth"
    metric = bytes([0x0A]) + varint(len(name)) + name + bytes([0x20, 11, 0x70, 1])
    return bytes([0x12]) + varint(len(metric)) + metric


def subscribe(broker, topics):
    # Into a file, not a pipe: a DDATA of 64 metrics is 10 kB of hex, and a pipe read only
    # at the end would fill, stop the subscriber and make the broker drop what it sends.
    command = ["mosquitto_sub", "-p", str(broker), "-F", "%U %t %x"]
    for topic in topics:
        command += ["-t", topic]
    output = tempfile.TemporaryFile(mode="w+")
    listener = subprocess.Popen(command, stdout=output, text=True)
    listener.output = output
    time.sleep(0.5)
    return listener


def received(listener):
    """(time, topic, payload bytes) of what the subscriber took, once it is stopped."""
    listener.terminate()
    listener.wait()
    listener.output.seek(0)
    for line in listener.output.read().splitlines():
        parts = line.split(" ")
        if len(parts) != 3:
            continue  # the last line cut by terminate()
        try:
            yield float(parts[0]), parts[1], bytes.fromhex(parts[2])
        except ValueError:
            continue


def metric_value(payload, name):
    for metric in payload.get("metrics", []):
        if metric.get("name") == name:
            return metric.get("value")
    return None


def latency(args):
    listener = subscribe(args.broker, [args.topic])
    feed = socket.create_connection(("127.0.0.1", args.feed_port))
    feed.setblocking(False)
    probe_sent = {}
    start = time.monotonic()
    sequence = 0
    speed = 0
    batch = max(1, int(args.rate / 1000))  # every millisecond: probes must not wait in a batch
    while time.monotonic() - start < args.seconds:
        lines = []
        for _ in range(batch):
            sequence += 1
            values = [(sequence * 7 + i * 13) % 1000 for i in range(64)]
            if sequence % args.probe_every == 0:
                speed = 1 + (sequence // args.probe_every) % 30000
                probe_sent[speed] = None
            values[1] = speed
            lines.append(json.dumps({"addr": 5, "slot": 0, "offset": 0, "values": values}) + "\n")
        data = "".join(lines).encode()
        sent_at = time.time()
        while data:
            try:
                data = data[feed.send(data):]
            except BlockingIOError:
                time.sleep(0.0005)
        for key, value in probe_sent.items():
            if value is None:
                probe_sent[key] = sent_at
        try:
            while feed.recv(65536):  # what the bridge sends its drivers
                pass
        except BlockingIOError:
            pass
        delay = start + sequence / args.rate - time.monotonic()
        if delay > 0:
            time.sleep(delay)
    elapsed = time.monotonic() - start
    time.sleep(0.5)
    first_seen = {}
    ddata = 0
    for stamp, _, payload in received(listener):
        ddata += 1
        decoded = sparkplug_decode.payload(payload)
        value = metric_value(decoded, "engine_speed")
        if value in probe_sent and value not in first_seen:
            first_seen[value] = (stamp, decoded.get("timestamp", 0) / 1000)
    latencies = [(first_seen[v][0] - probe_sent[v]) * 1000 for v in first_seen]
    # The DDATA's timestamp is the bridge's clock when it looked: the bridge's share of the
    # latency (the same host's clock; to the millisecond the payload has).
    bridge = [(first_seen[v][1] - probe_sent[v]) * 1000 for v in first_seen]
    result = {"telegrams": sequence, "per_second": round(sequence / elapsed), "probes": len(probe_sent),
              "seen": len(latencies), "ddata": ddata}
    if len(latencies) >= 2:
        result["p50_ms"] = round(statistics.median(latencies), 1)
        result["p99_ms"] = round(statistics.quantiles(latencies, n=100)[98], 1)
        result["max_ms"] = round(max(latencies), 1)
        result["bridge_p50_ms"] = round(statistics.median(bridge), 1)
        result["bridge_p99_ms"] = round(statistics.quantiles(bridge, n=100)[98], 1)
    print(json.dumps(result))


def births(args):
    node_topics = [f"spBv1.0/{args.group}/+/{args.node}", f"spBv1.0/{args.group}/+/{args.node}/+"]
    listener = subscribe(args.broker, node_topics)
    publisher = mqtt_connect(args.broker, "bench-rebirth")
    requests = []
    for _ in range(args.rounds):
        requests.append(time.time())
        mqtt_publish(publisher, f"spBv1.0/{args.group}/NCMD/{args.node}", rebirth_payload())
        time.sleep(args.spacing)
    publisher.close()
    messages = list(received(listener))
    rounds = []
    for i, asked in enumerate(requests):
        until = requests[i + 1] if i + 1 < len(requests) else float("inf")
        these = [(t, topic, p) for t, topic, p in messages if asked <= t < until and "BIRTH" in topic.split("/")[2]]
        nbirth = [m for m in these if m[1].split("/")[2] == "NBIRTH"]
        dbirth = [m for m in these if m[1].split("/")[2] == "DBIRTH"]
        if not nbirth or not dbirth:
            rounds.append({"births": len(these)})
            continue
        rounds.append({"bytes": sum(len(p) for _, _, p in these),
                       "nbirth_bytes": len(nbirth[0][2]),
                       "devices": [m[1].split("/")[-1] for m in dbirth],
                       "metrics": sum(len(sparkplug_decode.payload(p).get("metrics", [])) for _, _, p in these),
                       "ms": round((max(t for t, _, _ in these) - asked) * 1000, 1)})
    done = [r for r in rounds if "ms" in r]
    result = {"rounds": rounds}
    if done:
        result["bytes"] = max(r["bytes"] for r in done)
        result["devices"] = done[-1]["devices"]
        result["metrics"] = done[-1]["metrics"]
        result["median_ms"] = round(statistics.median(r["ms"] for r in done), 1)
        result["max_ms"] = max(r["ms"] for r in done)
    print(json.dumps(result))


def main():
    parser = argparse.ArgumentParser()
    modes = parser.add_subparsers(dest="mode", required=True)
    lat = modes.add_parser("latency")
    lat.add_argument("--feed-port", type=int, required=True)
    lat.add_argument("--broker", type=int, required=True)
    lat.add_argument("--topic", required=True)
    lat.add_argument("--rate", type=float, default=1000)
    lat.add_argument("--seconds", type=float, default=5)
    lat.add_argument("--probe-every", type=int, default=20)
    birth = modes.add_parser("births")
    birth.add_argument("--broker", type=int, required=True)
    birth.add_argument("--group", required=True)
    birth.add_argument("--node", required=True)
    birth.add_argument("--rounds", type=int, default=5)
    birth.add_argument("--spacing", type=float, default=5.5)
    args = parser.parse_args()
    latency(args) if args.mode == "latency" else births(args)


if __name__ == "__main__":
    main()
