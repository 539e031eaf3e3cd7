#!/usr/bin/env python3
"""What watches a bridge over HTTP during bench/http.sh: a front page listening to
/api/events, and a Prometheus scrape imitated by GET /metrics every second. Bounded by
--seconds. Prints one JSON line: the event bytes and events the page received, the size
of its first, full picture, and the scrapes answered.
"""
import argparse
import http.client
import json
import socket
import time


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--port", type=int, required=True)
    parser.add_argument("--seconds", type=float, default=5)
    args = parser.parse_args()
    page = socket.create_connection(("127.0.0.1", args.port), timeout=1)
    page.sendall(b"GET /api/events HTTP/1.1\r\nHost: 127.0.0.1\r\nAccept: text/event-stream\r\n\r\n")
    received = b""
    start = time.monotonic()
    next_scrape = start
    scrapes = 0
    while time.monotonic() - start < args.seconds:
        if time.monotonic() >= next_scrape:
            scraper = http.client.HTTPConnection("127.0.0.1", args.port, timeout=2)
            scraper.request("GET", "/metrics")
            scrapes += scraper.getresponse().status == 200
            scraper.close()
            next_scrape += 1
        try:
            received += page.recv(65536)
        except socket.timeout:
            pass
    elapsed = time.monotonic() - start
    body = received.split(b"\r\n\r\n", 1)[1] if b"\r\n\r\n" in received else b""
    events = [e for e in body.split(b"\n\n") if e.startswith(b"event: ")]
    # The first picture: the panel, every register, the last monitor lines.
    first, later = events[:3], events[3:-1]  # the last may be cut
    by_name = {}
    for event in later:
        name = event.split(b"\n", 1)[0][7:].decode()
        by_name[name] = by_name.get(name, 0) + len(event) + 2
    print(json.dumps({"seconds": elapsed, "events": len(later), "bytes_by_event": by_name,
                      "full_values_bytes": sum(len(e) + 2 for e in first[:2]), "scrapes": scrapes}))


if __name__ == "__main__":
    main()
