#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets into fuzz/corpus/<target>/ (docs/fuzzing.md).

The seeds are what the targets' inputs look like on a good day: the Modbus frames of the
seeds (seed 004 §5.1/§5.2, seed 002 §6 — their CRCs are the seeds' own), the example
configs of config/examples/ and the YAML of the docs, the feed lines and recordings of
docs/feed.md, the filter expressions of the monitor's help and docs. Each target's file
format (its first byte, its records) is described at the top of its *_fuzzer.cpp.

Run it again after changing a format or the docs it reads; the files are kept in git.
Files this script did not write (inputs a fuzzer found and someone added) are left alone.
"""

import zlib
import pathlib
import re
import struct

ROOT = pathlib.Path(__file__).resolve().parent.parent
CORPUS = ROOT / "fuzz" / "corpus"


def crc16(data: bytes) -> bytes:
    """Modbus RTU CRC-16, low byte first on the wire (Modbus over Serial Line V1.02 §6.2.2)."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return bytes([crc & 0xFF, crc >> 8])


def rtu(body: str) -> bytes:
    """An RTU frame from its address and PDU in hex, with its CRC."""
    data = bytes.fromhex(body)
    return data + crc16(data)


def mbap(transaction: int, unit: int, pdu: bytes) -> bytes:
    return transaction.to_bytes(2, "big") + b"\x00\x00" + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu


# Seed 004 §5.1 and §5.2 (the Bridge), seed 002 §6 (the stepper driver): as on the wire.
SEED_RTU = {
    "seed004-read-query": bytes.fromhex("01 04 00 11 00 02 21 CE"),
    "seed004-read-response": bytes.fromhex("01 04 04 00 50 7F FF 9B E5"),
    "seed004-write-query": bytes.fromhex("01 06 01 01 09 29 1E 78"),
    "seed002-read-query": bytes.fromhex("01 03 00 00 00 02 C4 0B"),
    "seed002-read-response": bytes.fromhex("01 03 04 00 B4 00 08 BB D3"),
    "seed002-write-coil": bytes.fromhex("01 05 00 07 FF 00 3D FB"),
    "seed002-write-register": bytes.fromhex("01 06 00 01 00 04 D9 C9"),
    "seed002-write-multiple-query": bytes.fromhex("01 10 00 09 00 02 04 00 C8 00 00 B2 3B"),
    "seed002-write-multiple-response": bytes.fromhex("01 10 00 09 00 02 91 CA"),
}
for name, frame in SEED_RTU.items():
    assert crc16(frame[:-2]) == frame[-2:], name

# Seed 004 §5.1/§5.2 over TCP.
SEED_TCP = {
    "seed004-tcp-read-query": bytes.fromhex("12 34 00 00 00 06 01 04 00 11 00 02"),
    "seed004-tcp-read-response": bytes.fromhex("12 34 00 00 00 07 01 04 04 00 50 7F FF"),
    "seed004-tcp-write-query": bytes.fromhex("12 34 00 00 00 06 01 06 01 01 09 29"),
}

# Requests for the banks of config/examples/four-devices.yaml at the seed's default bases
# (seed 004 §6.1, docs/registers.md): reads of A, C+0x13, D1, S1, W and the read block
# 0x0200; writes to W, X and the write block 0x0201; function 43/14.
BANK_PDUS = {
    "read-a": "04 1000 0010",
    "read-c-online-bits": "04 1033 0001",
    "read-d1-fn3": "03 1100 0040",
    "read-d1-to-d2": "04 1130 0020",
    "read-s1": "04 2100 0014",
    "read-w": "03 3000 0011",
    "read-block": "04 0200 0001",
    "read-too-many": "04 1000 007C",
    "write-w": "06 3003 04D2",
    "write-x": "06 3010 0005",
    "write-block": "06 0201 0929",
    "write-multiple-w": "10 3000 0003 06 0001 0002 0003",
    "device-identification": "2B 0E 01 00",
    "device-identification-one": "2B 0E 04 04",
    "unknown-function": "07",
}


def pdu(text: str) -> bytes:
    return bytes.fromhex(text)


def write(target: str, name: str, data: bytes) -> None:
    directory = CORPUS / target
    directory.mkdir(parents=True, exist_ok=True)
    (directory / re.sub(r"[^A-Za-z0-9_-]", "_", name)).write_bytes(data)


def mbap_request() -> None:
    # Byte 0: slave set-up (0x10: the plant on-line; 0x07 bits switch extensions off).
    for name, frame in SEED_TCP.items():
        if "query" in name:
            write("mbap_request", name, b"\x00" + frame)
    for n, (name, text) in enumerate(BANK_PDUS.items()):
        write("mbap_request", name, b"\x10" + mbap(n + 1, 1, pdu(text)))
    pipelined = b"".join(mbap(n, 1 if n % 3 else 0xFF, pdu(t)) for n, t in enumerate(BANK_PDUS.values()))
    write("mbap_request", "pipelined", b"\x10" + pipelined)
    write("mbap_request", "another-unit", b"\x00" + mbap(7, 9, pdu(BANK_PDUS["read-a"])))
    write("mbap_request", "extensions-off", b"\x07" + mbap(1, 1, pdu(BANK_PDUS["read-d1-fn3"]))
          + mbap(2, 1, pdu(BANK_PDUS["write-multiple-w"])) + mbap(3, 1, pdu(BANK_PDUS["device-identification"])))
    write("mbap_request", "half-an-adu", b"\x00" + SEED_TCP["seed004-tcp-read-query"][:9])


def chunks(*frames: bytes, silence: int = 40, split: bool = False) -> bytes:
    """rtu_framer records: [n][silence in 100 µs] n bytes; `split` sends a byte at a time."""
    out = b""
    for frame in frames:
        pieces = [frame[i:i + 1] for i in range(len(frame))] if split else [frame]
        for k, piece in enumerate(pieces):
            out += bytes([len(piece), silence if k == 0 else 0]) + piece
    return out


def rtu_framer() -> None:
    # Byte 0: 0x02 19200 baud, 0x40 the bridge is slave 2 (so slave 1's exchanges are
    # foreign), 0x08 an exact frame gap, 0x10/0x20 an adapter latency of 1/16 ms.
    s = SEED_RTU
    write("rtu_framer", "seed004-read-for-the-bridge", b"\x02" + chunks(s["seed004-read-query"]))
    write("rtu_framer", "seed004-write-for-the-bridge", b"\x02" + chunks(s["seed004-write-query"]))
    write("rtu_framer", "seed004-foreign-exchange",
          b"\x42" + chunks(s["seed004-read-query"], s["seed004-read-response"], s["seed004-write-query"],
                           s["seed004-write-query"]))
    write("rtu_framer", "seed002-foreign-exchanges",
          b"\x42" + chunks(s["seed002-read-query"], s["seed002-read-response"], s["seed002-write-coil"],
                           s["seed002-write-coil"], s["seed002-write-register"], s["seed002-write-register"],
                           s["seed002-write-multiple-query"], s["seed002-write-multiple-response"]))
    write("rtu_framer", "seed004-byte-by-byte", b"\x12" + chunks(s["seed004-read-query"], split=True))
    write("rtu_framer", "seed002-back-to-back", b"\x4A" + chunks(s["seed002-read-query"] + s["seed002-read-response"],
                                                                 silence=0))
    write("rtu_framer", "broadcast-write", b"\x02" + chunks(rtu("00 06 3003 04D2")))
    write("rtu_framer", "bank-reads",
          b"\x22" + chunks(*(rtu("01" + BANK_PDUS[n].replace(" ", "")) for n in ("read-a", "read-d1-fn3", "read-s1"))))
    write("rtu_framer", "device-identification", b"\x02" + chunks(rtu("01 2B 0E 01 00")))
    write("rtu_framer", "foreign-exception", b"\x42" + chunks(s["seed004-read-query"], rtu("01 84 02")))
    write("rtu_framer", "bad-crc-then-good",
          b"\x02" + chunks(s["seed004-read-query"][:-1] + b"\x00", s["seed004-read-query"], silence=0))
    write("rtu_framer", "truncated-then-silence", b"\x02" + chunks(s["seed004-read-query"][:5]) + b"\x00\xff")


# docs/feed.md: the input telegrams and the recording.
def feed_doc_lines() -> tuple[list[str], list[str]]:
    text = (ROOT / "docs" / "feed.md").read_text()
    lines = [line for line in text.splitlines() if line.startswith('{"addr"')]
    recorded = [line for line in text.splitlines() if line.startswith('{"t"')]
    assert lines and recorded, "docs/feed.md has no feed lines or recordings any more"
    return lines, recorded


def feed_line() -> None:
    # Byte 0: odd, the line limit of SPEC §6 (64 KiB); even, a limit of 8 + byte/2 % 64.
    lines, recorded = feed_doc_lines()
    for n, line in enumerate(lines):
        write("feed_line", f"docs-feed-{n}", b"\x01" + line.encode() + b"\n")
    write("feed_line", "docs-feed-all-crlf", b"\x01" + "".join(line + "\r\n" for line in lines).encode())
    write("feed_line", "docs-feed-split-reads", b"\x01" + "\xff".join(lines[0][i:i + 7] for i in range(0, len(lines[0]), 7)).encode("latin-1") + b"\n")
    write("feed_line", "docs-recorded", b"\x01" + "\n".join(recorded).encode() + b"\n")
    # chp-site.yaml: D1, D3 and D4 share address 2 (a unit's components), S1 at address 1.
    for name, line in {
        "shared-address-unnamed": '{"addr":2,"slot":0,"offset":0,"values":[1,2,3]}',
        "shared-address-named": '{"addr":2,"slot":0,"device":"uvr","offset":3,"values":[1500]}',
        "io-module": '{"addr":1,"slot":1,"offset":16,"values":[255,1]}',
        "past-the-end": '{"addr":3,"slot":0,"device":"nsu2","offset":60,"values":[1,2,3,4,5,6,7,8]}',
        "too-large-number": '{"addr":2,"slot":0,"offset":0,"values":[1e400]}',
        "negative": '{"addr":2,"slot":0,"offset":1,"values":[-32768,65535]}',
        "unknown-key": '{"addr":2,"slot":0,"offset":0,"values":[1],"x\\n":1}',
        "not-json": "addr=2",
    }.items():
        write("feed_line", name, b"\x01" + line.encode() + b"\n")
    write("feed_line", "overlong", b"\x00" + lines[0].encode() + b"\n" + lines[1].encode() + b"\n")


def command_filter() -> None:
    # The expression, a newline, the query's address and PDU.
    expressions = ["ad=3 fn=6 from=0x0200 to=0x0210", "", "fn=4", "fn=0x10", "ad=xx fn=xx from=xx to=xx",
                   "ad=1,fn=4", "from=0x0011 to=0x0011", "to=0x0100", "from=0xFFFF"]
    queries = [SEED_RTU["seed004-read-query"][:-2], SEED_RTU["seed004-write-query"][:-2],
               SEED_RTU["seed002-write-multiple-query"][:-2], bytes.fromhex("01 17 0010 0002 0300 0001 02 0001"),
               bytes.fromhex("01 2B 0E 01 00")]
    for n, expression in enumerate(expressions):
        write("command_filter", f"expression-{n}", expression.encode() + b"\n" + queries[n % len(queries)])


def basic_auth() -> None:
    # A users file, a 0x00, an Authorization header (basic_auth_fuzzer.cpp); or a header alone.
    import base64
    users = ("technician:$6$rounds=5000$Vbkm1V2IU1p3LXN7$ykIgySEG0r0.bMfhqUlZNhXcmKAUwM9Wl4Zqk2N5l0Ch6vY4dm6G2dU7TGmHdm"
             "SYXPj3e0DqS7u4Ey9AGF0Ge1\n# a comment\nviewer:$2b$12$abcdefghijklmnopqrstuuJ1Vd7zFv7cFDbEPSgk3gGDkzHmQ2bW6\n")
    headers = ["Basic " + base64.b64encode(b"technician:tech pass").decode(), "basic " + base64.b64encode(b"viewer:").decode(),
               "Basic " + base64.b64encode(b"nobody:x").decode().rstrip("="), "Basic " + base64.b64encode(b"no colon").decode(),
               "Bearer abc", "Basic ", "Basic !!!!", "BASIC dGVjaG5pY2lhbjp0ZWNoIHBhc3M="]
    for n, header in enumerate(headers):
        write("basic_auth", f"header-{n}", header.encode())
        write("basic_auth", f"users-and-header-{n}", users.encode() + b"\x00" + header.encode())
    write("basic_auth", "users-bad-line", b"technician\n\x00" + headers[0].encode())
    write("basic_auth", "users-twice", (users + users).encode() + b"\x00" + headers[0].encode())


def source_ref() -> None:
    # Byte 0: 0x00 D1..D4 as in config/examples/four-devices.yaml; 0x80 a bit is wanted.
    analog = ["D1.oil_temperature", "D1+0x01", "D2+0x28", "S1+0x00", "W+0x00", "C+0x00", "D1.engine_speed"]
    bits = ["D1+0x11.7", "S1+0x10.0", "X.0", "S1+0x11.1", "D1+0x11.8", "D1.remote_start", "D1+0x15.3"]
    for ref in analog:
        write("source_ref", f"analog-{ref}", b"\x00" + ref.encode())
    for ref in bits:
        write("source_ref", f"bit-{ref}", b"\x80" + ref.encode())


def config_loader() -> None:
    for path in sorted((ROOT / "config" / "examples").glob("*.yaml")):
        write("config_loader", f"example-{path.stem}", path.read_bytes())
    for doc in ("configuration", "lines", "master", "quickstart", "rtu"):
        text = (ROOT / "docs" / f"{doc}.md").read_text()
        for n, block in enumerate(re.findall(r"```yaml\n(.*?)```", text, re.S)):
            write("config_loader", f"docs-{doc}-{n}", block.encode())
    write("config_loader", "replay-dev-null",
          b"unimabus:\n  transport: replay\n  file: /dev/null\n  loop: true\n  speed: 2\n"
          b"  record: { file: rec.jsonl, max_size: 1MB, max_files: 3 }\n"
          b"devices:\n  D1: { type: unigen-chp, address: 5 }\n")


def master_codec() -> None:
    # Byte 0: the function's index in 1,2,3,4,5,6,15,16 (0x07), TCP framing (0x80), block
    # types (0x78); bytes 1..4: first register and count - 1, big-endian; byte 5: the slave.
    def request(fn_index: int, first: int, count: int, device: int = 1, tcp: bool = False, types: int = 0) -> bytes:
        return bytes([fn_index | types | (0x80 if tcp else 0)]) + first.to_bytes(2, "big") + (count - 1).to_bytes(2, "big") + bytes([device])

    s = SEED_RTU
    write("master_codec", "seed004-read", request(3, 0x0011, 2) + s["seed004-read-response"])
    write("master_codec", "seed004-read-tcp", request(3, 0x0011, 2, tcp=True) + SEED_TCP["seed004-tcp-read-response"])
    write("master_codec", "seed004-read-dint", request(3, 0x0011, 2, types=0x10) + s["seed004-read-response"])
    write("master_codec", "seed004-write", request(5, 0x0101, 1) + s["seed004-write-query"])
    write("master_codec", "seed002-read", request(2, 0x0000, 2) + s["seed002-read-response"])
    write("master_codec", "seed002-read-real", request(2, 0x0000, 2, types=0x20) + s["seed002-read-response"])
    write("master_codec", "seed002-write-coil", request(4, 0x0007, 1) + s["seed002-write-coil"])
    write("master_codec", "seed002-write-register", request(5, 0x0001, 1) + s["seed002-write-register"])
    write("master_codec", "seed002-write-multiple", request(7, 0x0009, 2) + s["seed002-write-multiple-response"])
    write("master_codec", "exception-02", request(3, 0x0010, 8) + rtu("01 84 02"))
    write("master_codec", "exception-02-tcp", request(3, 0x0010, 8, tcp=True) + mbap(1, 1, pdu("84 02")))
    write("master_codec", "read-coils", request(0, 0x0013, 10) + rtu("01 01 02 CD 01"))
    write("master_codec", "read-inputs", request(1, 0x00C4, 22) + rtu("01 02 03 AC DB 35"))
    write("master_codec", "wrong-address", request(3, 0x0011, 2, device=2) + s["seed004-read-response"])


def replay_reader() -> None:
    # Byte 0: the speed (1, 0.001, 1000, 2.5 by its low two bits), 0x04 loop.
    _, recorded = feed_doc_lines()
    write("replay_reader", "docs-recording", b"\x00" + "\n".join(recorded).encode() + b"\n")
    write("replay_reader", "docs-recording-looped", b"\x06" + "\n\n".join(recorded).encode())
    write("replay_reader", "docs-recording-crlf", b"\x01" + "".join(line + "\r\n" for line in recorded).encode())
    write("replay_reader", "t-goes-back", b"\x00" + (recorded[1] + "\n" + recorded[0]).encode())
    write("replay_reader", "all-at-zero", b"\x04" + ('{"t":0,"addr":5,"slot":0,"offset":0,"values":[1]}\n' * 3).encode())
    write("replay_reader", "late", b"\x01" + b'{"t":1e9,"addr":5,"slot":1,"offset":0,"values":[1]}\n')


def state_journal() -> None:
    header = b"unima-bridge state 1\n"

    def record(kind: str, index: int, value: int, continued: bool = False) -> bytes:
        body = f"{kind} {index} {value}" + (" +" if continued else "")
        return f"{body} {zlib.crc32(body.encode()):08x}\n".encode()

    records = record("W", 0, 1234) + record("W", 15, 65535) + record("X", 0, 5) + record("O", 1, 77) + record("O", 16, 0)
    write("state_journal", "empty", b"")
    write("state_journal", "header-only", header)
    write("state_journal", "every-kind", header + records)
    write("state_journal", "overwritten", header + record("W", 3, 1) + record("W", 3, 2))
    write("state_journal", "torn-tail", header + records + record("W", 2, 9)[:-4])
    write("state_journal", "torn-header", header[:9])
    write("state_journal", "damaged-middle", header + record("W", 1, 1).replace(b"1 1", b"1 2") + records)
    write("state_journal", "bad-index", header + record("W", 16, 1) + record("O", 0, 1))
    write("state_journal", "other-version", b"unima-bridge state 2\n" + records)
    write("state_journal", "crlf", header.replace(b"\n", b"\r\n") + records)
    one_write = record("W", 10, 7, True) + record("W", 11, 8, True) + record("X", 0, 3)
    write("state_journal", "one-write-of-three", header + records + one_write)
    write("state_journal", "torn-write", header + records + one_write[: len(one_write) // 2])


def client_hello(maximum=None, ciphers=None) -> bytes:
    """A real ClientHello, from OpenSSL's client (Python's ssl module over memory)."""
    import ssl
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    context.check_hostname = False
    context.verify_mode = ssl.CERT_NONE
    if maximum:
        context.maximum_version = maximum
    if ciphers:
        context.set_ciphers(ciphers)
    outgoing = ssl.MemoryBIO()
    client = context.wrap_bio(ssl.MemoryBIO(), outgoing)
    try:
        client.do_handshake()
    except ssl.SSLWantReadError:
        pass
    return outgoing.read()


def tls_session() -> None:
    # fuzz/tls_session_fuzzer.cpp: byte 0 the size of the pieces (0: all at once), then
    # what the client sends. The ClientHellos differ each time this runs (their random and
    # key share are fresh); the parser they reach does not.
    import ssl
    hello13 = client_hello()
    hello12 = client_hello(ssl.TLSVersion.TLSv1_2, "ECDHE-ECDSA-AES128-GCM-SHA256")
    alert = bytes([21, 3, 3, 0, 2, 2, 40])  # a fatal handshake_failure, in the clear
    change_cipher_spec = bytes([20, 3, 3, 0, 1, 1])
    write("tls_session", "client-hello-tls13", b"\x00" + hello13)
    write("tls_session", "client-hello-tls12", b"\x00" + hello12)
    write("tls_session", "client-hello-in-pieces", b"\x07" + hello13)
    write("tls_session", "client-hello-byte-by-byte", b"\x01" + hello12)
    write("tls_session", "client-hello-then-alert", b"\x00" + hello13 + alert)
    write("tls_session", "client-hello-then-change-cipher-spec", b"\x00" + hello13 + change_cipher_spec + bytes([23, 3, 3, 0, 17]) + bytes(17))
    write("tls_session", "client-hello-twice", b"\x00" + hello12 + hello12)
    write("tls_session", "not-tls", b"\x00GET / HTTP/1.1\r\nHost: bridge\r\n\r\n")
    write("tls_session", "modbus-in-the-clear", b"\x00" + SEED_TCP["seed004-tcp-read-query"])


def pb_varint(value: int) -> bytes:
    """A protobuf base-128 varint, low seven bits first ("Encoding" guide)."""
    out = b""
    while value >= 0x80:
        out += bytes([value & 0x7F | 0x80])
        value >>= 7
    return out + bytes([value])


def pb(field: int, value) -> bytes:
    """A protobuf field: an int as a varint, bytes as length-delimited, ("f", x) as a
    fixed32 float, ("d", x) as a fixed64 double."""
    if isinstance(value, tuple):
        kind, number = value
        return pb_varint(field << 3 | (5 if kind == "f" else 1)) + struct.pack("<f" if kind == "f" else "<d", number)
    if isinstance(value, int):
        return pb_varint(field << 3) + pb_varint(value)
    if isinstance(value, str):
        value = value.encode()
    return pb_varint(field << 3 | 2) + pb_varint(len(value)) + value


def sparkplug_metric(name=None, alias=None, datatype=None, value_field=None, value=None, null=False, props=b"") -> bytes:
    """Payload.Metric (Sparkplug 3.0 §6.4.3): name 1, alias 2, timestamp 3, datatype 4,
    is_null 7, properties 9, the value in field 10..16."""
    out = pb(1, name) if name is not None else b""
    out += pb(2, alias) if alias is not None else b""
    out += pb(3, 1700000000000)
    out += pb(4, datatype) if datatype is not None else b""
    out += pb(7, 1) if null else b""
    out += pb(9, props) if props else b""
    out += pb(value_field, value) if value_field else b""
    return out


def sparkplug_payload() -> None:
    # fuzz/sparkplug_payload_fuzzer.cpp: the MQTT payload, all of it. Commands as a host
    # sends them (NCMD rebirth, DCMD by name and by alias), births as the bridge sends
    # them (bdSeq, engUnit, nulls), and the corners of protobuf's format.
    def payload(*metrics: bytes, seq=None) -> bytes:
        out = pb(1, 1700000000123) + b"".join(pb(2, m) for m in metrics)
        return out + (pb(3, seq) if seq is not None else b"")

    eng_unit = pb(1, "engUnit") + pb(2, pb(1, 12) + pb(8, "°C"))
    write("sparkplug_payload", "ncmd-rebirth", payload(sparkplug_metric("Node Control/Rebirth", None, 11, 14, 1)))
    write("sparkplug_payload", "dcmd-w-float", payload(sparkplug_metric("w_03", None, 9, 12, ("f", -1.5))))
    write("sparkplug_payload", "dcmd-w-double", payload(sparkplug_metric("w_00", None, 10, 13, ("d", 21.5))))
    write("sparkplug_payload", "dcmd-x-by-alias", payload(sparkplug_metric(None, 42, 6, 10, 5)))
    write("sparkplug_payload", "dcmd-int16-sign-extended", payload(sparkplug_metric("w_01", None, 2, 10, 0xFFFFFFA9)))
    write("sparkplug_payload", "dcmd-uint32-in-long", payload(sparkplug_metric("x", None, 7, 11, 4294967295)))
    write("sparkplug_payload", "nbirth", payload(sparkplug_metric("bdSeq", None, 4, 11, 3),
                                                 sparkplug_metric("Node Control/Rebirth", None, 11, 14, 0), seq=0))
    write("sparkplug_payload", "dbirth-units-and-nulls",
          payload(sparkplug_metric("engine_speed", 1, 6, 10, 1500, props=eng_unit),
                  sparkplug_metric("mains_active_power", 2, 9, null=True, props=eng_unit),
                  sparkplug_metric("display_line1_chars_01_02", 3, 12, 15, "KO"), seq=1))
    nested = pb(1, "set") + pb(2, pb(1, 20) + pb(9, pb(1, "Quality") + pb(2, pb(1, 3) + pb(3, 192))))
    write("sparkplug_payload", "nested-property-sets", payload(sparkplug_metric("n", None, 6, 10, 1, props=nested)))
    write("sparkplug_payload", "unknown-fields-and-group",
          payload(sparkplug_metric("m", None, 11, 14, 1) + pb(31, 7)) + pb(6, 1) + bytes([0x33, 0x08, 0x01, 0x34]))
    write("sparkplug_payload", "empty", b"")


def table_ids(folder: str) -> list[str]:
    ids = []
    for path in sorted((ROOT / folder).glob("*.yaml")):
        ids += re.findall(r"^id: (\S+)$", path.read_text(), re.M)
        ids += [a.strip() for line in re.findall(r"^aliases: \[(.*)\]$", path.read_text(), re.M) for a in line.split(",")]
    return ids


def write_dictionary(target: str, words: list[str]) -> None:
    """A libFuzzer dictionary (fuzz/<target>.dict): the words of the format, which a
    mutation rarely spells by chance."""
    lines = [f'"{word}"' for word in sorted(set(words))]
    (ROOT / "fuzz" / f"{target}.dict").write_text("# Written by fuzz/make_seed_corpus.py.\n" + "\n".join(lines) + "\n")


BANKS = ["A", "B", "C", "D1", "D2", "D3", "D4", "S1", "S2", "S3", "S4", "S5", "S6", "S7", "W", "X"]


def dictionaries() -> None:
    # The config's keys and words (every lower-case string literal of the loader and its
    # sections), bank names, device types and profiles, and the pieces of numbers, sources
    # and durations.
    loader = "".join(path.read_text() for path in sorted((ROOT / "config").glob("*.cpp")))
    loader += (ROOT / "monitor" / "monitor_config.hpp").read_text()
    words = re.findall(r'"([a-z][a-z0-9_]*)"', loader)
    words += BANKS + [b + "+0x" for b in BANKS] + table_ids("banks/tables") + table_ids("master/profiles")
    words += ["0x", ".0", ".15", "xx", "true", "false", "ms", "s", "m", "MB", "KB", "unix:", ": ", "- ", "{ ", " }", "[ ",
              " ]", "~", "mqtt://", "mqtts://", "127.0.0.1:1883", "3.1.1"]
    write_dictionary("config_loader", words)
    feed = ["addr", "slot", "device", "offset", "values", "t"]
    feed_words = [f'\\"{key}\\":' for key in feed] + table_ids("banks/tables") + ["[", "]", "{", "}"]
    write_dictionary("feed_line", feed_words)
    write_dictionary("replay_reader", feed_words)
    write_dictionary("state_journal", ["unima-bridge state 1\\x0A", "W ", "X ", "O ", "\\x0A", " 0", " 65535", " +", " 00000000"])


for make in (mbap_request, rtu_framer, feed_line, command_filter, source_ref, config_loader, master_codec,
             replay_reader, state_journal, tls_session, basic_auth, sparkplug_payload, dictionaries):
    make()
