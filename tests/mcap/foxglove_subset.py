#!/usr/bin/env python3
"""Checks that every JSON Schema in our MCAP files is one Foxglove Studio and Lichtblick can load.

    python3 tests/mcap/foxglove_subset.py DIR       (CI: DIR = target/tmp/mcap-check, filled by `cargo test`)
    python3 tests/mcap/foxglove_subset.py --self-test

Foxglove (1.48) and Lichtblick turn a channel's JSON Schema into message definitions with `parseJsonSchema`
(packages/mcap-support/src/parseJsonSchema.ts) and drop the channel when it throws ("Error in topic /tracer/raw
(channel 16): Unsupported type undefined for dir"). That parser reads a subset of JSON Schema; the rules below
restate it (this is our own reading, written from the rules, not a copy):

  * a schema, and every nested object schema, has "type": "object"; its fields are its "properties";
  * a property with "oneOf" is an enumeration: every alternative must have a numeric "const" (no other form);
  * otherwise the property has exactly one "type" string out of boolean, string, number, integer, object,
    array. A list of types, "null", or no "type" (an "enum" alone) is refused;
  * a string may have "contentEncoding" only "base64";
  * an array has an "items" schema whose one "type" is boolean, string (no contentEncoding), number, integer
    or object (checked as an object schema); nothing else (no arrays of arrays);
  * an object property is checked as an object schema.

As a JSON value cannot be null where the schema gives one type, messages must leave an absent field out: the
checker also fails on any `null` inside a message.

Exits 1 with every failure listed; 2 when DIR holds no MCAP file. Needs: pip install mcap.
"""

import json
import os
import sys

from mcap.exceptions import McapError
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader

SCALARS = {"boolean", "number", "integer"}


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def object_problems(schema, where):
    """Why Foxglove's parser would refuse this object schema (an empty list if it would take it)."""
    if not isinstance(schema, dict) or schema.get("type") != "object":
        kind = schema.get("type") if isinstance(schema, dict) else schema
        return [f'{where}: expected "type": "object", got {json.dumps(kind)}']
    problems = []
    properties = schema.get("properties", {})
    if not isinstance(properties, dict):
        return [f"{where}: properties is not an object"]
    for name, field in properties.items():
        path = f"{where}.{name}"
        if not isinstance(field, dict):
            problems.append(f"{path}: the property's schema is not an object")
            continue
        if isinstance(field.get("oneOf"), list):
            if not all(isinstance(alt, dict) and is_number(alt.get("const")) for alt in field["oneOf"]):
                problems.append(f"{path}: oneOf alternatives must all have a numeric const")
            continue
        problems.extend(field_problems(field, path))
    return problems


def field_problems(field, path, item=False):
    """Why the parser would refuse a property (`item`: an array's items, which take no contentEncoding and no
    nested array)."""
    kind = field.get("type")
    if isinstance(kind, str) and kind in SCALARS:
        return []
    if kind == "string":
        encoding = field.get("contentEncoding")
        allowed = (None,) if item else (None, "base64")
        return [] if encoding in allowed else [f"{path}: unsupported contentEncoding {json.dumps(encoding)}"]
    if kind == "object":
        return object_problems(field, path)
    if kind == "array" and not item:
        items = field.get("items")
        if not isinstance(items, dict):
            return [f"{path}: an array needs one \"items\" schema"]
        return field_problems(items, path + "[]", item=True)
    what = "array item type" if item else "type"
    return [f"{path}: unsupported {what} {json.dumps(kind)} (one of boolean, string, number, integer, object"
            f"{'' if item else ', array'})"]


def null_paths(value, where):
    """Where a message holds null."""
    if value is None:
        return [where]
    if isinstance(value, dict):
        return [path for key, item in value.items() for path in null_paths(item, f"{where}.{key}")]
    if isinstance(value, list):
        return [path for index, item in enumerate(value) for path in null_paths(item, f"{where}[{index}]")]
    return []


def check_file(path):
    """Failures of one file: its schemas against the subset, its messages for nulls (the first few each)."""
    failures, schemas, channels, nulls = [], {}, {}, {}
    with open(path, "rb") as stream:
        try:
            for record in StreamReader(stream, skip_magic=False, emit_chunks=False).records:
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, Message) and record.channel_id in channels:
                    topic = channels[record.channel_id].topic
                    if topic not in nulls:
                        found = null_paths(json.loads(record.data), topic)
                        if found:
                            nulls[topic] = found
        except (McapError, EOFError, ValueError) as error:
            # A recording killed mid-way ends in a cut record: what came before is what Foxglove loads.
            if not path.endswith(".killed.mcap"):
                failures.append(f"{path}: {error}")
    if not schemas:
        failures.append(f"{path}: no schema")
    for schema in schemas.values():
        if schema.encoding != "jsonschema":
            failures.append(f"{path}: schema {schema.name} has encoding {schema.encoding!r}")
            continue
        failures.extend(f"{path}: {problem}" for problem in object_problems(json.loads(schema.data), schema.name))
    failures.extend(f"{path}: a message holds null at {found[0]}" for found in nulls.values())
    return failures, len(schemas)


def self_test():
    """The rules refuse what Foxglove refused (tracer.raw before the fix) and accept Foxglove's own schemas."""
    old_raw = {"type": "object", "properties": {
        "ts_ns": {"type": ["integer", "null"]}, "iface": {"type": "string"},
        "dir": {"enum": ["rx", "tx", None]}, "wire": {"enum": ["can-v2", None]}}}
    problems = object_problems(old_raw, "tracer.raw")
    assert [p.split(":")[0] for p in problems] == ["tracer.raw.ts_ns", "tracer.raw.dir", "tracer.raw.wire"], problems
    assert "unsupported type null" in problems[1], problems
    refused = {
        "null type": {"type": "null"},
        "oneOf of strings": {"oneOf": [{"const": "a"}]},
        "oneOf of booleans": {"oneOf": [{"const": True}]},
        "hex encoding": {"type": "string", "contentEncoding": "hex"},
        "array without items": {"type": "array"},
        "array of arrays": {"type": "array", "items": {"type": "array", "items": {"type": "number"}}},
        "array of base64": {"type": "array", "items": {"type": "string", "contentEncoding": "base64"}},
        "nested bad": {"type": "object", "properties": {"x": {"type": ["number", "null"]}}},
        "array of bad objects": {"type": "array", "items": {"type": "object", "properties": {"x": {}}}},
    }
    for name, field in refused.items():
        assert object_problems({"type": "object", "properties": {"f": field}}, "t"), name
    assert object_problems({"properties": {}}, "t"), "a root without type object"
    accepted = {"type": "object", "properties": {
        "timestamp": {"type": "object", "properties": {"sec": {"type": "integer", "minimum": 0}}},
        "level": {"oneOf": [{"title": "INFO", "const": 2}, {"title": "ERROR", "const": 4}]},
        "data": {"type": "string", "contentEncoding": "base64"},
        "wire": {"type": "string", "enum": ["can-v2", "serial"]},
        "faults": {"type": "array", "items": {"type": "string"}},
        "poses": {"type": "array", "items": {"type": "object", "properties": {"x": {"type": "number"}}}},
        "ok": {"type": "boolean"}}}
    assert object_problems(accepted, "t") == [], object_problems(accepted, "t")
    assert null_paths({"a": {"b": [1, None]}, "c": 0}, "/t") == ["/t.a.b[1]"]
    print("foxglove_subset.py self-test: ok")


def main():
    arguments = sys.argv[1:]
    if arguments == ["--self-test"]:
        return self_test()
    if len(arguments) != 1:
        sys.exit(__doc__)
    directory = arguments[0]
    paths = sorted(os.path.join(directory, f) for f in os.listdir(directory) if f.endswith(".mcap")) \
        if os.path.isdir(directory) else []
    if not paths:
        print(f"foxglove_subset.py: no .mcap file in {directory}: the tests wrote none", file=sys.stderr)
        sys.exit(2)
    failures, schemas = [], 0
    for path in paths:
        found, count = check_file(path)
        failures.extend(found)
        schemas += count
    for failure in failures:
        print(f"FOXGLOVE SUBSET FAIL: {failure}", file=sys.stderr)
    if failures:
        sys.exit(1)
    print(f"foxglove_subset.py: {schemas} schemas in {len(paths)} files fit Foxglove's JSON Schema parser; no null in any message")


if __name__ == "__main__":
    main()
