#!/usr/bin/env python3
"""Reads every MCAP file the tests wrote with Foxglove's own Python reader, as Foxglove and PlotJuggler users would.

    python3 tests/mcap/verify.py DIR      (CI: DIR = target/tmp/mcap-check, filled by `cargo test`)
    python3 tests/mcap/verify.py --self-test   (the checker catches a bad file: run by CI first)
    python3 tests/mcap/verify.py DIR --layout docs/foxglove-layout.json

For each DIR/NAME.mcap:
  * the file is finished (summary, statistics and indexes present) and read both ways: indexed (seeking) and
    streamed, with the same messages; a NAME ending in `.killed` is a recording killed mid-way (SIGKILL): it is
    streamed as far as it goes and only what was read is checked;
  * every channel has message encoding `json` and a schema with encoding `jsonschema` that is a valid JSON Schema;
    the well-known channels carry Foxglove's schema names (foxglove.Log, foxglove.PoseInFrame,
    foxglove.FrameTransform);
  * every message parses as JSON and validates against its channel's schema;
  * log times never decrease in file order, and publish time equals log time;
  * the statistics record's counts equal the messages read;
  * a metadata record `tracerctl` names the version, sources, protocol and command;
  * when NAME.jsonl is beside it (decode's `--format json` of the same input): /tracer/raw holds one message per
    line, and each /tracer/<msg> channel (motors split by number) one per line of that `msg`.
With --layout, the suggested Foxglove layout is checked against the files: every topic a panel shows is written
by them, with Foxglove's schema where the panel needs one, and every plotted field is in its topic's schema.
Exits 1 with every failure listed; 2 when DIR holds no MCAP file (a CI step that checked nothing must not pass).
Needs: pip install mcap jsonschema.
"""

import collections
import json
import os
import sys

import jsonschema
from mcap.reader import SeekingReader
from mcap.records import Channel, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap.exceptions import McapError

WELL_KNOWN = {"/tracer/events": "foxglove.Log", "/tracer/pose": "foxglove.PoseInFrame", "/tf": "foxglove.FrameTransform"}
NOT_MESSAGES = {"raw", "remote_request", "error_frame", "invalid"}
METADATA_KEYS = {"version", "sources", "protocol", "command"}


def topic_of(line):
    """The typed channel a `decode --format json` line lands on, or None."""
    msg = line["msg"]
    if msg in NOT_MESSAGES:
        return None
    if msg == "motor_high_speed":
        return f"/tracer/motor/{line['fields']['motor']}"
    if msg == "motor_low_speed":
        return f"/tracer/motor/{line['fields']['motor']}/low_speed"
    return f"/tracer/{msg}"


def read_all(path, killed):
    """(channels, schemas, messages, metadata, statistics) read from path; messages in file order."""
    channels, schemas, messages, metadata = {}, {}, [], {}
    with open(path, "rb") as stream:
        try:
            for record in StreamReader(stream, skip_magic=False, emit_chunks=False, validate_crcs=True).records:
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, Message):
                    messages.append(record)
                elif isinstance(record, Metadata):
                    metadata[record.name] = record.metadata
        except (McapError, EOFError, ValueError) as error:
            if not killed:
                raise
            print(f"  {os.path.basename(path)}: readable up to {len(messages)} messages ({error!r})")
    statistics = None
    if not killed:
        with open(path, "rb") as stream:
            reader = SeekingReader(stream, validate_crcs=True)
            summary = reader.get_summary()
            if summary is None or summary.statistics is None:
                raise McapError("no summary or statistics: the file was not finished")
            statistics = summary.statistics
            indexed = sum(1 for _ in reader.iter_messages(log_time_order=False))
            if indexed != len(messages):
                raise McapError(f"indexed read found {indexed} messages, streamed {len(messages)}")
    return channels, schemas, messages, metadata, statistics


def layout_failures(layout_path, topics):
    """What in the layout names a topic or field that no file has; `topics`: topic -> (schema name, schema)."""
    with open(layout_path, encoding="utf-8") as stream:
        layout = json.load(stream)
    failures, panels = [], layout["configById"]

    def leaves(node):
        return [node] if isinstance(node, str) else leaves(node["first"]) + leaves(node["second"])

    for panel in leaves(layout["layout"]):
        if panel not in panels:
            failures.append(f"layout: panel {panel} is placed but has no configuration")
    needs = []
    for panel, config in panels.items():
        kind = panel.split("!")[0]
        if kind == "Plot":
            needs += [(panel, path["value"], None) for path in config["paths"]]
        elif kind == "RosOut":
            needs.append((panel, config["topicToRender"], "foxglove.Log"))
        elif kind == "3D":
            needs += [(panel, topic, None) for topic in config["topics"]]
        elif kind == "RawMessages":
            needs.append((panel, config["topicPath"], None))
    for panel, path, schema_name in needs:
        topic, _, field = path.partition(".")
        if topic not in topics:
            failures.append(f"layout: {panel} shows {topic}, which no file has")
            continue
        name, schema = topics[topic]
        if schema_name and name != schema_name:
            failures.append(f"layout: {panel} needs {schema_name} on {topic}, the files have {name}")
        if field and field not in schema.get("properties", {}):
            failures.append(f"layout: {panel} plots {path}, but {topic}'s schema has no {field!r}")
    return failures


def check_file(path, topics=None):
    failures = []
    name = os.path.basename(path)[: -len(".mcap")]
    killed = name.endswith(".killed")
    try:
        channels, schemas, messages, metadata, statistics = read_all(path, killed)
    except Exception as error:  # noqa: BLE001 - any reader error is a failure of this file
        return [f"{name}: cannot read: {error!r}"], 0

    validators = {}
    for channel in channels.values():
        schema = schemas.get(channel.schema_id)
        if channel.message_encoding != "json":
            failures.append(f"{name}: {channel.topic}: message encoding {channel.message_encoding!r}, not json")
        if schema is None or schema.encoding != "jsonschema":
            failures.append(f"{name}: {channel.topic}: schema encoding is not jsonschema")
            continue
        expected = WELL_KNOWN.get(channel.topic)
        if expected and schema.name != expected:
            failures.append(f"{name}: {channel.topic}: schema {schema.name!r}, expected {expected!r}")
        try:
            document = json.loads(schema.data)
            validator = jsonschema.validators.validator_for(document)
            validator.check_schema(document)
            validators[channel.id] = validator(document)
            if topics is not None:
                topics[channel.topic] = (schema.name, document)
        except (ValueError, jsonschema.SchemaError) as error:
            failures.append(f"{name}: {channel.topic}: schema {schema.name!r} is not a valid JSON Schema: {error}")

    counts = collections.Counter()
    previous = None
    invalid_shown = 0
    for index, message in enumerate(messages):
        topic = channels[message.channel_id].topic
        counts[topic] += 1
        if previous is not None and message.log_time < previous:
            failures.append(f"{name}: message {index} ({topic}): log time {message.log_time} < {previous}")
        previous = message.log_time
        if message.publish_time != message.log_time:
            failures.append(f"{name}: message {index} ({topic}): publish time differs from log time")
        try:
            value = json.loads(message.data)
        except ValueError as error:
            failures.append(f"{name}: message {index} ({topic}) is not JSON: {error}")
            continue
        validator = validators.get(message.channel_id)
        if validator is not None:
            errors = list(validator.iter_errors(value))
            if errors and invalid_shown < 5:
                invalid_shown += 1
                failures.append(f"{name}: message {index} ({topic}) fails its schema: {errors[0].message}")

    if statistics is not None:
        by_id = {channel.topic: statistics.channel_message_counts.get(channel.id, 0) for channel in channels.values()}
        if statistics.message_count != len(messages):
            failures.append(f"{name}: statistics say {statistics.message_count} messages, read {len(messages)}")
        for topic, count in by_id.items():
            if count != counts[topic]:
                failures.append(f"{name}: {topic}: statistics say {count} messages, read {counts[topic]}")
        record = metadata.get("tracerctl")
        if record is None:
            failures.append(f"{name}: no metadata record named tracerctl")
        elif not METADATA_KEYS <= set(record):
            failures.append(f"{name}: metadata tracerctl lacks {sorted(METADATA_KEYS - set(record))}")

    jsonl = os.path.join(os.path.dirname(path), name + ".jsonl")
    if os.path.exists(jsonl) and not killed:
        with open(jsonl, encoding="utf-8") as lines:
            decoded = [json.loads(line) for line in lines if line.strip()]
        if counts["/tracer/raw"] != len(decoded):
            failures.append(f"{name}: /tracer/raw has {counts['/tracer/raw']} messages, decode wrote {len(decoded)} lines")
        expected = collections.Counter(t for t in map(topic_of, decoded) if t)
        for topic in sorted(set(expected) | {t for t in counts if t.startswith("/tracer/") and t not in
                                             ("/tracer/raw", "/tracer/events", "/tracer/pose")}):
            if counts[topic] != expected[topic]:
                failures.append(f"{name}: {topic}: {counts[topic]} messages, decode's JSON has {expected[topic]}")
    return failures, len(messages)


def self_test():
    """Writes a good file and bad ones with Foxglove's Python writer; the checker must pass and fail them."""
    import tempfile
    from mcap.writer import Writer

    def write(path, message, log_times=(1, 2), metadata=True, jsonl=None):
        with open(path, "wb") as stream:
            writer = Writer(stream)
            writer.start()
            schema = writer.register_schema(
                "tracer.system_state", "jsonschema",
                json.dumps({"type": "object", "properties": {"battery_voltage": {"type": "number"}},
                            "required": ["battery_voltage"]}).encode())
            channel = writer.register_channel("/tracer/system_state", "json", schema)
            raw = writer.register_channel("/tracer/raw", "json", writer.register_schema(
                "tracer.raw", "jsonschema", b'{"type":"object"}'))
            for time in log_times:
                writer.add_message(channel, log_time=time, publish_time=time, data=json.dumps(message).encode())
                writer.add_message(raw, log_time=time, publish_time=time, data=b"{}")
            if metadata:
                writer.add_metadata("tracerctl", {key: "x" for key in METADATA_KEYS})
            writer.finish()
        if jsonl is not None:
            with open(path[: -len(".mcap")] + ".jsonl", "w", encoding="utf-8") as out:
                out.write("".join(json.dumps({"msg": "system_state", "fields": {}}) + "\n" for _ in range(jsonl)))

    cases = [
        ("good", {}, True),
        ("wrong_type", {"message": {"battery_voltage": "25.9"}}, False),
        ("decreasing_time", {"log_times": (2, 1)}, False),
        ("no_metadata", {"metadata": False}, False),
        ("count_differs", {"jsonl": 3}, False),
    ]
    failed = []
    with tempfile.TemporaryDirectory() as directory:
        for name, options, should_pass in cases:
            path = os.path.join(directory, name + ".mcap")
            message = options.pop("message", {"battery_voltage": 25.9})
            write(path, message, **options)
            found, _ = check_file(path)
            if (not found) != should_pass:
                failed.append(f"{name}: expected {'pass' if should_pass else 'failure'}, got {found}")
            os.remove(path)
        # The layout checker: a plotted field the schema has passes, one it lacks fails.
        path = os.path.join(directory, "layout.mcap")
        write(path, {"battery_voltage": 25.9})
        topics = {}
        check_file(path, topics)
        for field, should_pass in (("battery_voltage", True), ("no_such_field", False)):
            layout_path = os.path.join(directory, "layout.json")
            with open(layout_path, "w", encoding="utf-8") as out:
                json.dump({"configById": {"Plot!a": {"paths": [{"value": f"/tracer/system_state.{field}"}]}},
                           "layout": "Plot!a"}, out)
            found = layout_failures(layout_path, topics)
            if (not found) != should_pass:
                failed.append(f"layout plotting {field}: expected {'pass' if should_pass else 'failure'}, got {found}")
    cases += [("layout", {}, True)] * 2
    for failure in failed:
        print(f"self-test: {failure}")
    print(f"self-test: {len(cases) - len(failed)} of {len(cases)} cases judged right")
    return 1 if failed else 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    arguments = sys.argv[1:]
    layout = None
    if len(arguments) == 3 and arguments[1] == "--layout":
        layout = arguments[2]
        arguments = arguments[:1]
    if len(arguments) != 1:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    directory = arguments[0]
    paths = sorted(os.path.join(directory, f) for f in os.listdir(directory) if f.endswith(".mcap")) \
        if os.path.isdir(directory) else []
    if not paths:
        print(f"verify.py: no .mcap file in {directory}: the tests wrote none", file=sys.stderr)
        return 2
    failures, total, topics = [], 0, {}
    for path in paths:
        found, messages = check_file(path, topics)
        failures += found
        total += messages
        print(f"{'FAIL' if found else 'ok  '} {os.path.basename(path)}: {messages} messages")
    if layout:
        found = layout_failures(layout, topics)
        failures += found
        print(f"{'FAIL' if found else 'ok  '} {layout}: every panel's topic and field is in the files")
    print(f"{len(paths)} MCAP files, {total} messages, {len(failures)} failures")
    for failure in failures:
        print(f"  - {failure}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
