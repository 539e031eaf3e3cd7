#!/usr/bin/env python3
"""One HTTPS GET to the daemon's HTTP server (SPEC §13 with http.tls and http.users),
with Python's ssl and http.client: the server's certificate checked against CA.

  https_get.py PORT PATH CA [NAME:PASSWORD] [--first BYTES] [--repeat N] [--close]

Prints "server: <CN>", "status: <code>", "www-authenticate: <value>" when there is one,
then "body: <the body, or its first BYTES for an event stream>"; or "error: <reason>".
--repeat N sends the request N times at once, each on a new connection and with the
password followed by its number (PASSWORD1, PASSWORD2 …), and prints
"statuses: <code> <code> ..." only. --close sends "Connection: close" over a bare TLS
socket, reads to the end and prints "end: close_notify" when the server ended with its
close_notify alert, "end: cut" when the connection ended without one.
"""
import base64
import http.client
import socket
import ssl
import sys


def read_to_the_end(port, path, context, headers):
    """The raw answer to one request with "Connection: close", and how the server ended it."""
    with socket.create_connection(("127.0.0.1", port), timeout=5) as raw:
        # suppress_ragged_eofs off: an end without close_notify is an error, not b"".
        with context.wrap_socket(raw, server_hostname="127.0.0.1", suppress_ragged_eofs=False) as tls:
            lines = [f"GET {path} HTTP/1.1", "Host: 127.0.0.1", "Connection: close"]
            lines += [f"{name}: {value}" for name, value in headers.items()]
            tls.sendall(("\r\n".join(lines) + "\r\n\r\n").encode())
            answer = b""
            try:
                while chunk := tls.recv(65536):
                    answer += chunk
                end = "close_notify"
            except (ssl.SSLEOFError, ConnectionResetError):
                end = "cut"
    return answer, end


def main():
    args = sys.argv[1:]
    close = "--close" in args
    if close:
        args.remove("--close")
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
    if close:
        try:
            answer, end = read_to_the_end(port, path, context, headers)
        except (OSError, ssl.SSLError) as e:
            print(f"error: {e}")
            return 1
        print("status: " + answer.split(b" ", 2)[1].decode() if answer.startswith(b"HTTP/1.1 ") else "status: none")
        print(f"end: {end}")
        return 0
    if "--repeat" in options:
        # Handshakes one after the other (a host may have only a few in progress), then
        # every request before any answer is read: they reach the server together however
        # slow the machine is.
        connections = []
        for _ in range(options["--repeat"]):
            connection = http.client.HTTPSConnection("127.0.0.1", port, context=context, timeout=10)
            connection.connect()
            connections.append(connection)
        for number, connection in enumerate(connections, 1):
            # Each its own password, as a guesser's: the same header would share one check.
            guess = dict(headers)
            if credentials:
                guess["Authorization"] = "Basic " + base64.b64encode(f"{credentials}{number}".encode()).decode()
            connection.request("GET", path, headers=guess)
        statuses = [str(connection.getresponse().status) for connection in connections]
        for connection in connections:
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
