#!/usr/bin/env python3
"""A Modbus/TCP Security client for the tests (SPEC §11), on Python's ssl module: TLS 1.2+
with a client certificate, then Modbus requests over the TLS stream.

  modbus_tls_client.py [--tls1.2 [--ciphers SUITES]] [--unit N] PORT CA [CERT KEY] -- REQUEST...

Each REQUEST is a PDU in hex ("0600000007", "0400110001"); for each one line is printed:
the response PDU in hex, or "error: <why>" (and the client stops) when the handshake or the
connection fails; first "server: <CN>" of the certificate the server presented, last
"version: TLSv1.x". --tls1.2 caps the client at TLS 1.2; --ciphers offers only those TLS 1.2
suites (OpenSSL's names); --unit sends to unit id N (default 1, the bridge's own). Exit
status 0 when every request was answered.

--leave MS: sends the first request only, and MS ms later closes the session (its
close_notify, then the socket) without waiting for the answer; prints "left".
"""

import socket
import ssl
import struct
import sys
import time


def main() -> int:
    args = sys.argv[1:]
    tls12_only = args[0] == "--tls1.2"
    if tls12_only:
        args = args[1:]
    ciphers = None
    if args[0] == "--ciphers":
        ciphers, args = args[1], args[2:]
    unit = 1
    if args[0] == "--unit":
        unit, args = int(args[1]), args[2:]
    leave_ms = None
    if args[0] == "--leave":
        leave_ms, args = int(args[1]), args[2:]
    split = args.index("--")
    port, ca, *identity = args[:split]
    requests = args[split + 1:]
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    context.minimum_version = ssl.TLSVersion.TLSv1_2
    if tls12_only:
        context.maximum_version = ssl.TLSVersion.TLSv1_2
    if ciphers:
        context.set_ciphers(ciphers)
    context.load_verify_locations(ca)
    if identity:
        context.load_cert_chain(identity[0], identity[1])
    try:
        raw = socket.create_connection(("127.0.0.1", int(port)), timeout=5)
        stream = context.wrap_socket(raw, server_hostname="127.0.0.1")
        subject = dict(field[0] for field in stream.getpeercert()["subject"])
        print(f"server: {subject['commonName']}", flush=True)
        for transaction, request in enumerate(requests, start=1):
            pdu = bytes.fromhex(request)
            stream.sendall(struct.pack(">HHHB", transaction, 0, len(pdu) + 1, unit) + pdu)
            if leave_ms is not None:
                time.sleep(leave_ms / 1000)
                leave(stream)
                print("left", flush=True)
                return 0
            header = receive(stream, 7)
            answered, _, length, _ = struct.unpack(">HHHB", header)
            body = receive(stream, length - 1)
            if answered != transaction:
                raise OSError(f"answer to transaction {answered}, expected {transaction}")
            print(body.hex(), flush=True)
        print(f"version: {stream.version()}", flush=True)
        stream.close()
    except (OSError, ssl.SSLError) as e:
        print(f"error: {e}", flush=True)
        return 1
    return 0


def leave(stream: ssl.SSLSocket) -> None:
    """A clean close as a client sends it: close_notify, then the socket, whatever answers."""
    try:
        stream.settimeout(0.5)
        stream.unwrap()
    except (OSError, ssl.SSLError):
        pass
    stream.close()


def receive(stream: ssl.SSLSocket, n: int) -> bytes:
    data = b""
    while len(data) < n:
        chunk = stream.recv(n - len(data))
        if not chunk:
            raise OSError("connection closed by the server")
        data += chunk
    return data


if __name__ == "__main__":
    sys.exit(main())
