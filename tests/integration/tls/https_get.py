#!/usr/bin/env python3
"""One HTTPS GET to the daemon's HTTP server (SPEC §13 with http.tls and http.users),
with Python's ssl and http.client: the server's certificate checked against CA.

  https_get.py PORT PATH CA [NAME:PASSWORD] [--first BYTES] [--repeat N]

Prints "server: <CN>", "status: <code>", "www-authenticate: <value>" when there is one,
then "body: <the body, or its first BYTES for an event stream>"; or "error: <reason>".
--repeat N sends the request N times at once, each on a new connection, and prints
"statuses: <code> <code> ..." only.
"""
import base64
import http.client
import ssl
import sys


def main():
    args = sys.argv[1:]
    options = {}
    for name in ("--first", "--repeat"):
        if name in args:
            at = args.index(name)
            options[name] = int(args[at + 1])
            del args[at:at + 2]
    first = options.get("--first")
    port, path, ca = int(args[0]), args[1], args[2]
    credentials = args[3] if len(args) > 3 else None
    context = ssl.create_default_context(cafile=ca)
    headers = {}
    if credentials:
        headers["Authorization"] = "Basic " + base64.b64encode(credentials.encode()).decode()
    if "--repeat" in options:
        statuses = []
        for _ in range(options["--repeat"]):
            connection = http.client.HTTPSConnection("127.0.0.1", port, context=context, timeout=5)
            connection.request("GET", path, headers=headers)
            statuses.append(str(connection.getresponse().status))
            connection.close()
        print("statuses: " + " ".join(statuses))
        return 0
    connection = http.client.HTTPSConnection("127.0.0.1", port, context=context, timeout=5)
    try:
        connection.request("GET", path, headers=headers)
        # Before the response: the connection lets its socket go once a closing response is read.
        subject = dict(item for rdn in connection.sock.getpeercert()["subject"] for item in rdn)
        response = connection.getresponse()
    except (OSError, ssl.SSLError, http.client.HTTPException) as e:
        print(f"error: {e}")
        return 1
    print(f"server: {subject.get('commonName')}")
    print(f"status: {response.status}")
    if response.getheader("WWW-Authenticate"):
        print(f"www-authenticate: {response.getheader('WWW-Authenticate')}")
    body = response.read(first) if first else response.read()
    print("body: " + body.decode(errors="replace").replace("\n", "\\n"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
