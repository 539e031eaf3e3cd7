#!/usr/bin/env python3
"""An MQTT 3.1.1 broker over TLS, just enough for one client, that sends a burst of
commands as brokers that batch their writes do (EMQX, HiveMQ): many PUBLISH packets in one
TLS record. mosquitto writes one record a packet, so a client that stops reading after a
packet finds the next one in its socket; here the rest of the record waits in the client's
TLS library, where the socket does not show it (tests/integration/mqtt_test.cpp).

Usage: batching_broker.py PORT CERTIFICATE KEY COMMAND_TOPIC COUNT
Once the client subscribed to a filter ending in /set/#, publishes COMMAND_TOPIC with the
payloads 1..COUNT at QoS 0, 16,000 bytes of packets a record; then answers PINGREQ and
nothing else (no PUBACK), so that nothing but the burst makes the client's socket readable.
Says "listening" when it listens.
"""
import socket
import ssl
import sys


def remaining_length(n):
    out = bytearray()
    while True:
        byte, n = n % 128, n // 128
        out.append(byte | (0x80 if n else 0))
        if not n:
            return bytes(out)


def packet(first_byte, body):
    return bytes([first_byte]) + remaining_length(len(body)) + body


def read_exactly(conn, n):
    data = b""
    while len(data) < n:
        chunk = conn.recv(n - len(data))
        if not chunk:
            raise EOFError
        data += chunk
    return data


def read_packet(conn):
    first = read_exactly(conn, 1)[0]
    length, shift = 0, 0
    while True:
        byte = read_exactly(conn, 1)[0]
        length |= (byte & 0x7F) << shift
        shift += 7
        if not byte & 0x80:
            break
    return first, read_exactly(conn, length)


def main():
    port, certificate, key, topic, count = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4].encode(), int(sys.argv[5])
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.load_cert_chain(certificate, key)
    listener = socket.create_server(("127.0.0.1", port))
    print("listening", flush=True)
    raw, _ = listener.accept()
    conn = context.wrap_socket(raw, server_side=True)
    burst = b"".join(packet(0x30, len(topic).to_bytes(2, "big") + topic + str(value).encode())
                     for value in range(1, count + 1))
    try:
        while True:
            kind, body = read_packet(conn)
            if kind >> 4 == 1:  # CONNECT
                conn.sendall(packet(0x20, b"\x00\x00"))
            elif kind >> 4 == 8:  # SUBSCRIBE: packet id, then (filter, options) pairs
                filters, at = [], 2
                while at < len(body):
                    size = int.from_bytes(body[at:at + 2], "big")
                    filters.append(body[at + 2:at + 2 + size])
                    at += 2 + size + 1
                conn.sendall(packet(0x90, body[:2] + bytes([1] * len(filters))))
                if any(f.endswith(b"/set/#") for f in filters):
                    for start in range(0, len(burst), 16000):
                        conn.sendall(burst[start:start + 16000])  # one TLS record each
            elif kind >> 4 == 12:  # PINGREQ
                conn.sendall(packet(0xD0, b""))
    except (EOFError, ConnectionError, ssl.SSLError):
        pass


if __name__ == "__main__":
    main()
