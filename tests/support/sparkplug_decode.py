#!/usr/bin/env python3
"""Decodes a Sparkplug B payload and prints it as JSON: the tests' independent reader.

Written from the Eclipse Sparkplug 3.0.0 specification (chapter 6 "Payloads": the field
numbers of Payload, Metric, PropertySet, PropertyValue and PropertySetList, and the data
types of §6.4.16–17) and from the "Encoding" guide of Protocol Buffers (varints, tags,
wire types) — not from the bridge's C++ (sparkplug/), which the tests check against it.
Python's standard library only: no protobuf package.

    sparkplug_decode.py [FILE]        # the payload's bytes; standard input without FILE
    sparkplug_decode.py --hex HEX     # the bytes as hex digits

Output, the specification's own JSON notation (§6.4.1) with each field only when present:
    {"timestamp": N, "seq": N, "uuid": "...", "body": "<hex>",
     "metrics": [{"name": "...", "alias": N, "timestamp": N, "datatype": "Int16",
                  "is_historical": b, "is_transient": b, "is_null": b,
                  "properties": {"engUnit": {"type": "String", "value": "°C"}},
                  "field": "int_value", "value": -87}]}
"value" is read as the datatype says (an Int16's int_value as the two's complement of its
16 bits, whether the sender sign-extended it or not); "field" names the protobuf field that
held it. Exit status 1 and a line on stderr when the bytes are no payload.
"""

import json
import struct
import sys

DATA_TYPES = [
    "Unknown", "Int8", "Int16", "Int32", "Int64", "UInt8", "UInt16", "UInt32", "UInt64",
    "Float", "Double", "Boolean", "String", "DateTime", "Text", "UUID", "DataSet", "Bytes",
    "File", "Template", "PropertySet", "PropertySetList", "Int8Array", "Int16Array",
    "Int32Array", "Int64Array", "UInt8Array", "UInt16Array", "UInt32Array", "UInt64Array",
    "FloatArray", "DoubleArray", "BooleanArray", "StringArray", "DateTimeArray",
]
SIGNED_BITS = {"Int8": 8, "Int16": 16, "Int32": 32, "Int64": 64}

VARINT, I64, LEN, SGROUP, EGROUP, I32 = 0, 1, 2, 3, 4, 5


class NotAPayload(Exception):
    pass


def fields(data: bytes):
    """Yields (number, wire type, value) for each field of one message; groups skipped."""
    pos = 0

    def varint():
        nonlocal pos
        value, shift = 0, 0
        while True:
            if pos >= len(data):
                raise NotAPayload("truncated varint")
            byte = data[pos]
            pos += 1
            value |= (byte & 0x7F) << shift
            shift += 7
            if not byte & 0x80:
                if value >= 1 << 64:
                    raise NotAPayload("varint past 64 bits")
                return value
            if shift >= 70:
                raise NotAPayload("varint longer than 10 bytes")

    def take(n):
        nonlocal pos
        if pos + n > len(data):
            raise NotAPayload("length past the end")
        chunk = data[pos:pos + n]
        pos += n
        return chunk

    def skip_group(number):
        while True:
            key = varint()
            if key & 7 == EGROUP:
                if key >> 3 != number:
                    raise NotAPayload("unmatched end-group")
                return
            read_value(key & 7, key >> 3)

    def read_value(wire, number):
        if wire == VARINT:
            return varint()
        if wire == I64:
            return take(8)
        if wire == LEN:
            return take(varint())
        if wire == I32:
            return take(4)
        if wire == SGROUP:
            skip_group(number)
            return None
        raise NotAPayload(f"wire type {wire}")

    while pos < len(data):
        key = varint()
        number, wire = key >> 3, key & 7
        if number == 0:
            raise NotAPayload("field number 0")
        value = read_value(wire, number)
        if wire != SGROUP:
            yield number, wire, value


def expect(wire, wanted, what):
    if wire != wanted:
        raise NotAPayload(f"{what}: wire type {wire}, the schema's is {wanted}")


def integer(raw: int, datatype: str) -> int:
    """An integer field read as its Sparkplug type: signed types from their own bits."""
    bits = SIGNED_BITS.get(datatype)
    if bits is None:
        return raw
    raw &= (1 << bits) - 1
    return raw - (1 << bits) if raw >> (bits - 1) else raw


# The `oneof value` fields in the order Metric (from 10) and PropertyValue (from 3) share.
SCALARS = ["int_value", "long_value", "float_value", "double_value", "boolean_value", "string_value"]


def scalar(offset: int, wire: int, value, datatype: str):
    name = SCALARS[offset]
    if name in ("int_value", "long_value", "boolean_value"):
        expect(wire, VARINT, name)
        if name == "int_value":
            value &= 0xFFFFFFFF
        return name, (value != 0) if name == "boolean_value" else integer(value, datatype)
    if name == "float_value":
        expect(wire, I32, name)
        return name, struct.unpack("<f", value)[0]
    if name == "double_value":
        expect(wire, I64, name)
        return name, struct.unpack("<d", value)[0]
    expect(wire, LEN, name)
    return name, value.decode("utf-8", errors="replace")


def type_name(number: int) -> str:
    return DATA_TYPES[number] if number < len(DATA_TYPES) else f"DataType({number})"


def property_set(data: bytes) -> dict:
    keys, values = [], []
    for number, wire, value in fields(data):
        if number == 1:
            expect(wire, LEN, "PropertySet.keys")
            keys.append(value.decode("utf-8", errors="replace"))
        elif number == 2:
            expect(wire, LEN, "PropertySet.values")
            values.append(property_value(value))
    if len(keys) != len(values):
        raise NotAPayload("PropertySet: keys and values differ in number")
    return dict(zip(keys, values))


def property_value(data: bytes) -> dict:
    result = {}
    raw_value = None
    for number, wire, value in fields(data):
        if number == 1:
            expect(wire, VARINT, "PropertyValue.type")
            result["type"] = type_name(value & 0xFFFFFFFF)
        elif number == 2:
            expect(wire, VARINT, "PropertyValue.is_null")
            result["is_null"] = value != 0
        elif 3 <= number <= 11:
            raw_value = (number, wire, value)  # oneof: the last one counts
    if raw_value is not None:
        number, wire, value = raw_value
        if number <= 8:
            result["value"] = scalar(number - 3, wire, value, result.get("type", "Unknown"))[1]
        elif number == 9:
            expect(wire, LEN, "PropertyValue.propertyset_value")
            result["value"] = property_set(value)
        elif number == 10:
            expect(wire, LEN, "PropertyValue.propertysets_value")
            result["value"] = [property_set(v) for n, w, v in fields(value) if n == 1 and w == LEN]
        else:
            expect(wire, LEN, "PropertyValue.extension_value")
            result["value"] = value.hex()
    return result


def metric(data: bytes) -> dict:
    result = {}
    raw_value = None
    for number, wire, value in fields(data):
        if number == 1:
            expect(wire, LEN, "Metric.name")
            result["name"] = value.decode("utf-8", errors="replace")
        elif number in (2, 3):
            expect(wire, VARINT, "Metric.alias/timestamp")
            result["alias" if number == 2 else "timestamp"] = value
        elif number == 4:
            expect(wire, VARINT, "Metric.datatype")
            result["datatype"] = type_name(value & 0xFFFFFFFF)
        elif number in (5, 6, 7):
            expect(wire, VARINT, "Metric flag")
            result[{5: "is_historical", 6: "is_transient", 7: "is_null"}[number]] = value != 0
        elif number == 8:
            expect(wire, LEN, "Metric.metadata")
            result["metadata"] = value.hex()
        elif number == 9:
            expect(wire, LEN, "Metric.properties")
            result.setdefault("properties", {}).update(property_set(value))
        elif 10 <= number <= 19:
            raw_value = (number, wire, value)  # oneof: the last one counts
    if raw_value is not None:
        number, wire, value = raw_value
        if number <= 15:
            result["field"], result["value"] = scalar(number - 10, wire, value, result.get("datatype", "Unknown"))
        else:
            expect(wire, LEN, "Metric value")
            result["field"] = {16: "bytes_value", 17: "dataset_value", 18: "template_value", 19: "extension_value"}[number]
            result["value"] = value.hex()
    return result


def payload(data: bytes) -> dict:
    result = {}
    metrics = []
    for number, wire, value in fields(data):
        if number in (1, 3):
            expect(wire, VARINT, "Payload.timestamp/seq")
            result["timestamp" if number == 1 else "seq"] = value
        elif number == 2:
            expect(wire, LEN, "Payload.metrics")
            metrics.append(metric(value))
        elif number == 4:
            expect(wire, LEN, "Payload.uuid")
            result["uuid"] = value.decode("utf-8", errors="replace")
        elif number == 5:
            expect(wire, LEN, "Payload.body")
            result["body"] = value.hex()
    result["metrics"] = metrics
    return result


def main() -> int:
    args = sys.argv[1:]
    if args[:1] == ["--hex"]:
        data = bytes.fromhex("".join(args[1:]))
    elif args:
        with open(args[0], "rb") as f:
            data = f.read()
    else:
        data = sys.stdin.buffer.read()
    try:
        print(json.dumps(payload(data), ensure_ascii=False, sort_keys=True))
    except NotAPayload as problem:
        print(f"error: not a Sparkplug B payload: {problem}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
