//! The Foxglove side of a recording, read with the mcap crate's own reader: channels, schema
//! names and encodings, message counts, and the content of the messages.

mod common;

use common::frames;
use std::collections::BTreeMap;
use std::io::Cursor;
use vitro_record::{RecordOptions, Recorder, synthetic, topic};

#[test]
fn foxglove_channels_carry_the_well_known_schemas_and_a_message_per_frame() {
    let scene = synthetic::scene();
    let input = frames(&scene, 20, 9);
    let mut rec =
        Recorder::new(Cursor::new(Vec::new()), &scene, &RecordOptions::default()).unwrap();
    for f in &input {
        rec.frame(f).unwrap();
    }
    let stats = rec.stats();
    let bytes = rec.finish().unwrap().into_inner();

    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut schemas: BTreeMap<String, (String, String, String)> = BTreeMap::new();
    let mut last: BTreeMap<String, serde_json::Value> = BTreeMap::new();
    let mut times: BTreeMap<String, Vec<u64>> = BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let t = m.channel.topic.clone();
        let s = m
            .channel
            .schema
            .as_ref()
            .expect("every channel has a schema");
        schemas.insert(
            t.clone(),
            (
                s.name.clone(),
                s.encoding.clone(),
                m.channel.message_encoding.clone(),
            ),
        );
        *counts.entry(t.clone()).or_default() += 1;
        times.entry(t.clone()).or_default().push(m.log_time);
        last.insert(t, serde_json::from_slice(&m.data).expect("JSON message"));
    }
    assert_eq!(counts.values().sum::<usize>() as u64, stats.messages);
    let n = input.len();
    let want = [
        (topic::SCENE, "vitro.Scene", 1),
        (topic::FRAME, "vitro.Frame", n),
        (topic::MAP, "foxglove.SceneUpdate", 1),
        (topic::ENTITIES, "foxglove.SceneUpdate", n),
        (topic::DETECTIONS, "foxglove.SceneUpdate", n),
        (topic::INTENTIONS, "foxglove.SceneUpdate", n),
        (topic::SENSORS, "foxglove.SceneUpdate", n),
        (topic::TF, "foxglove.FrameTransforms", n),
        (topic::METRICS, "vitro.Metrics", n),
    ];
    for (t, schema, count) in want {
        assert_eq!(counts.get(t), Some(&count), "{t}");
        assert_eq!(
            schemas[t],
            (schema.to_owned(), "jsonschema".into(), "json".into()),
            "{t}"
        );
    }
    let logs: usize = input.iter().map(|f| f.messages.len() + f.log.len()).sum();
    assert_eq!(counts[topic::LOG], logs);
    assert_eq!(schemas[topic::LOG].0, "foxglove.Log");
    let gps: Vec<_> = counts
        .keys()
        .filter(|t| t.starts_with(topic::GPS_PREFIX))
        .collect();
    assert_eq!(gps.len(), 9);
    for t in gps {
        assert_eq!(counts[t], n);
        assert_eq!(schemas[t].0, "foxglove.LocationFix");
    }
    // Log time is simulated time.
    let frame_times: Vec<u64> = input.iter().map(|f| f.t_ns).collect();
    assert_eq!(times[topic::ENTITIES], frame_times);
    assert_eq!(times[topic::SCENE], [0]);

    // Contents: the last frame's entities, the map's layers, fixes near the origin.
    let f = input.last().unwrap();
    let entities = &last[topic::ENTITIES];
    assert_eq!(entities["deletions"][0]["type"], 1);
    let drawn = entities["entities"].as_array().unwrap();
    assert_eq!(drawn.len(), f.entities.len());
    assert_eq!(drawn[0]["id"], f.entities[0].name.as_str());
    assert_eq!(drawn[0]["texts"][0]["text"], f.entities[0].name.as_str());
    assert_eq!(
        last[topic::TF]["transforms"].as_array().unwrap().len(),
        f.entities.len()
    );
    let map_ids: Vec<&str> = last[topic::MAP]["entities"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["id"].as_str().unwrap())
        .collect();
    for layer in [
        "terrain",
        "streets",
        "paths",
        "bridges",
        "buildings",
        "forbidden",
    ] {
        assert!(map_ids.contains(&layer), "{layer} in {map_ids:?}");
    }
    let terrain = &last[topic::MAP]["entities"][0]["triangles"][0];
    let vertices = terrain["points"].as_array().unwrap().len();
    assert_eq!(vertices, scene.terrain.nx * scene.terrain.ny);
    let indices = terrain["indices"].as_array().unwrap();
    assert_eq!(
        indices.len(),
        6 * (scene.terrain.nx - 1) * (scene.terrain.ny - 1)
    );
    assert!(
        indices
            .iter()
            .all(|i| (i.as_u64().unwrap() as usize) < vertices)
    );
    let fix = &last[&format!("{}{}", topic::GPS_PREFIX, f.entities[0].name)];
    assert!((fix["latitude"].as_f64().unwrap() - scene.geo.lat0).abs() < 0.01);
    assert!((fix["longitude"].as_f64().unwrap() - scene.geo.lon0).abs() < 0.01);
    assert_eq!(last[topic::METRICS]["events"], f.events as f64);
    let detections = &last[topic::DETECTIONS]["entities"][0]["lines"][0];
    assert_eq!(
        detections["points"].as_array().unwrap().len(),
        2 * f.detections.len()
    );
    assert_eq!(
        detections["colors"].as_array().unwrap().len(),
        2 * f.detections.len()
    );
}
