#!/usr/bin/env python3
"""Checks a Vitro recording (MCAP) with the Python `mcap` reader, and optionally its KML export.

    pip install mcap
    python3 scripts/check_mcap.py RUN.mcap [--frames N] [--kml RUN.kml]

The file must open with its summary (statistics, channels, schemas); every channel must be
JSON with a `jsonschema` schema whose title is its name: vitro.Scene on /vitro/scene,
vitro.Frame on /vitro/frame, foxglove.SceneUpdate on /map, /entities, /detections,
/intentions and /sensors, foxglove.FrameTransforms on /tf, foxglove.Log on /log,
vitro.Metrics on /metrics, foxglove.LocationFix on each /gps/NAME. One scene and one map at
t = 0; one message per frame on every per-frame channel (N of them, if --frames is given);
the statistics agree with the messages read; each frame's log time is its t_ns, in order,
and its /entities update draws each of its entities; fixes are on the globe. With --kml: the
KML parses as XML, holds one gx:Track per entity seen, each with as many <when> as
<gx:coord>. Exits 1 on the first mismatch.
"""
import argparse
import json
import math
import sys
import xml.etree.ElementTree as ET
from collections import Counter

from mcap.reader import make_reader

PER_FRAME = {
    "/vitro/frame": "vitro.Frame",
    "/entities": "foxglove.SceneUpdate",
    "/detections": "foxglove.SceneUpdate",
    "/intentions": "foxglove.SceneUpdate",
    "/sensors": "foxglove.SceneUpdate",
    "/tf": "foxglove.FrameTransforms",
    "/metrics": "vitro.Metrics",
}
ONCE = {"/vitro/scene": "vitro.Scene", "/map": "foxglove.SceneUpdate"}
OTHER = {"/log": "foxglove.Log"}
GPS = "/gps/"
KML = "{http://www.opengis.net/kml/2.2}"
GX = "{http://www.google.com/kml/ext/2.2}"


def fail(msg):
    print(f"check_mcap: {msg}", file=sys.stderr)
    sys.exit(1)


def expected_schema(topic):
    if topic.startswith(GPS):
        return "foxglove.LocationFix"
    for table in (PER_FRAME, ONCE, OTHER):
        if topic in table:
            return table[topic]
    return None


def check_recording(path, frames_wanted):
    with open(path, "rb") as f:
        try:
            reader = make_reader(f)
            summary = reader.get_summary()
        except Exception as e:  # the reader raises its own exception types
            fail(f"{path}: not a readable, finished MCAP file: {e}")
        if summary is None or summary.statistics is None:
            fail(f"{path}: no summary with statistics (an unfinished recording?)")
        channels = summary.channels
        topics = {c.topic for c in channels.values()}
        for topic in list(PER_FRAME) + list(ONCE) + list(OTHER):
            if topic not in topics:
                fail(f"missing channel {topic}; channels: {sorted(topics)}")
        for c in channels.values():
            want = expected_schema(c.topic)
            schema = summary.schemas.get(c.schema_id)
            if want is None:
                fail(f"unexpected channel {c.topic}")
            if schema is None or schema.name != want:
                fail(f"{c.topic}: schema {schema.name if schema else None!r}, expected {want!r}")
            if schema.encoding != "jsonschema" or c.message_encoding != "json":
                fail(f"{c.topic}: encodings {schema.encoding!r}/{c.message_encoding!r}")
            title = json.loads(schema.data).get("title")
            if title != want:
                fail(f"{c.topic}: schema text titled {title!r}, expected {want!r}")

        counts = Counter()
        frame_times = []
        entity_ids = set()
        frame_entities = {}
        drawn = {}
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            topic = channel.topic
            counts[topic] += 1
            try:
                data = json.loads(message.data)
            except ValueError as e:
                fail(f"{topic}: a message at {message.log_time} ns is not JSON: {e}")
            if topic == "/vitro/frame":
                if data["t_ns"] != message.log_time:
                    fail(f"frame t_ns {data['t_ns']} logged at {message.log_time}")
                frame_times.append(message.log_time)
                entity_ids.update(e["id"] for e in data["entities"])
                frame_entities[message.log_time] = sorted(e["name"] for e in data["entities"])
            elif topic == "/entities":
                drawn[message.log_time] = sorted(e["id"] for e in data["entities"])
            elif topic == "/vitro/scene" or topic == "/map":
                if message.log_time != 0:
                    fail(f"{topic} logged at {message.log_time}, expected 0")
                if topic == "/vitro/scene":
                    for key in ("name", "geo", "terrain", "places"):
                        if key not in data:
                            fail(f"/vitro/scene lacks {key!r}")
            elif topic.startswith(GPS):
                lat, lon = data["latitude"], data["longitude"]
                if not (math.isfinite(lat) and -90 <= lat <= 90 and -180 <= lon <= 180):
                    fail(f"{topic}: fix off the globe: {lat}, {lon}")

    stats = summary.statistics.channel_message_counts
    for cid, c in channels.items():
        if stats.get(cid, 0) != counts[c.topic]:
            fail(f"{c.topic}: statistics say {stats.get(cid, 0)}, read {counts[c.topic]}")
    n = counts["/vitro/frame"]
    if n == 0:
        fail("no frames")
    if frames_wanted is not None and n != frames_wanted:
        fail(f"{n} frames, expected {frames_wanted}")
    for topic in PER_FRAME:
        if counts[topic] != n:
            fail(f"{topic}: {counts[topic]} messages for {n} frames")
    for topic in ONCE:
        if counts[topic] != 1:
            fail(f"{topic}: {counts[topic]} messages, expected 1")
    gps = [t for t in counts if t.startswith(GPS)]
    if len(gps) != len(entity_ids) or any(not 0 < counts[t] <= n for t in gps):
        fail(f"{len(gps)} /gps channels for {len(entity_ids)} entities")
    if frame_times != sorted(frame_times):
        fail("frames out of time order")
    if drawn != frame_entities:
        fail("the /entities updates do not draw each frame's entities")
    print(
        f"check_mcap: {path}: {n} frames, {len(entity_ids)} entities, "
        f"{sum(counts.values())} messages on {len(counts)} channels, "
        f"{counts['/log']} log lines: ok"
    )
    return len(entity_ids)


def check_kml(path, entities):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        fail(f"{path}: not well-formed XML: {e}")
    if root.tag != f"{KML}kml":
        fail(f"{path}: root element {root.tag}, expected kml")
    tracks = root.findall(f".//{GX}Track")
    if len(tracks) != entities:
        fail(f"{path}: {len(tracks)} tracks for {entities} entities")
    for t in tracks:
        whens = t.findall(f"{KML}when")
        coords = t.findall(f"{GX}coord")
        if not whens or len(whens) != len(coords):
            fail(f"{path}: a track with {len(whens)} times and {len(coords)} coordinates")
        for c in coords:
            lon, lat, _alt = map(float, c.text.split())
            if not (-90 <= lat <= 90 and -180 <= lon <= 180):
                fail(f"{path}: coordinate off the globe: {c.text}")
    print(f"check_mcap: {path}: {len(tracks)} tracks: ok")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("recording")
    parser.add_argument("--frames", type=int, help="the number of frames expected")
    parser.add_argument("--kml", help="the recording's KML export, to check too")
    args = parser.parse_args()
    entities = check_recording(args.recording, args.frames)
    if args.kml:
        check_kml(args.kml, entities)


if __name__ == "__main__":
    main()
