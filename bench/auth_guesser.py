#!/usr/bin/env python3
"""A peer guessing HTTP basic-auth passwords (bench/auth_guess.sh, issue 29): CONNECTIONS
threads, each sending GET /healthz with a new wrong password on a new connection from
SOURCE as soon as the last was answered, for SECONDS. Told to wait (429, 503), a thread
waits what Retry-After says, or --impatient seconds (a guesser that honours nothing).
Prints one JSON line: {"seconds": ..., "requests": ..., "statuses": {"401": n, ...}}.

  auth_guesser.py --port PORT [--source 127.0.0.2] [--connections 4] [--seconds 3]
                  [--impatient SECONDS]
"""
import argparse
import base64
import http.client
import itertools
import json
import threading
import time


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--port", type=int, required=True)
    parser.add_argument("--source", default="127.0.0.2")
    parser.add_argument("--connections", type=int, default=4)
    parser.add_argument("--seconds", type=float, default=3)
    parser.add_argument("--impatient", type=float)
    args = parser.parse_args()
    statuses = {}
    lock = threading.Lock()
    counter = itertools.count()
    end = time.monotonic() + args.seconds

    def guess():
        while time.monotonic() < end:
            credentials = f"technician:guess{next(counter)}".encode()
            headers = {"Authorization": "Basic " + base64.b64encode(credentials).decode()}
            try:
                connection = http.client.HTTPConnection("127.0.0.1", args.port, timeout=10,
                                                        source_address=(args.source, 0))
                connection.request("GET", "/healthz", headers=headers)
                response = connection.getresponse()
                status = str(response.status)
                retry_after = float(response.getheader("Retry-After", "1"))
                connection.close()
            except OSError as e:
                status = type(e).__name__
                retry_after = 1
            with lock:
                statuses[status] = statuses.get(status, 0) + 1
            if status in ("429", "503"):
                time.sleep(args.impatient if args.impatient is not None else retry_after)

    started = time.monotonic()
    threads = [threading.Thread(target=guess) for _ in range(args.connections)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    print(json.dumps({"seconds": time.monotonic() - started, "requests": sum(statuses.values()), "statuses": statuses}))


if __name__ == "__main__":
    main()
