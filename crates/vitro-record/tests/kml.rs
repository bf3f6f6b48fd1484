//! KML from a recording: well-formed XML, one track per entity, coordinates near the origin.

mod common;

use common::{frames, record, temp};
use quick_xml::events::Event;
use std::collections::BTreeMap;
use vitro_record::{RecordOptions, Replay, kml};

/// A parsed track: its number of `when` elements and its coordinates.
type Parsed = (usize, Vec<[f64; 3]>);

/// The tracks of a document, and the count of every element by name.
fn parse(doc: &str) -> (Vec<Parsed>, BTreeMap<String, usize>) {
    let mut reader = quick_xml::Reader::from_str(doc);
    reader.config_mut().trim_text(true);
    let mut tracks = Vec::new();
    let mut counts = BTreeMap::new();
    let mut stack: Vec<String> = Vec::new();
    loop {
        match reader.read_event().expect("well-formed XML") {
            Event::Start(e) => {
                let name = String::from_utf8(e.name().as_ref().to_vec()).unwrap();
                *counts.entry(name.clone()).or_insert(0) += 1;
                if name == "gx:Track" {
                    tracks.push((0, Vec::new()));
                }
                stack.push(name);
            }
            Event::End(_) => {
                stack.pop();
            }
            Event::Text(t) => {
                let text = t.decode().expect("text").into_owned();
                let track = tracks.last_mut();
                match (stack.last().map(String::as_str), track) {
                    (Some("when"), Some(track)) => track.0 += 1,
                    (Some("gx:coord"), Some(track)) => {
                        let v: Vec<f64> = text.split(' ').map(|x| x.parse().unwrap()).collect();
                        track.1.push([v[0], v[1], v[2]]);
                    }
                    _ => {}
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    assert!(stack.is_empty(), "every element closed");
    (tracks, counts)
}

#[test]
fn kml_has_a_track_per_entity_near_the_origin() {
    let path = temp("kml.mcap");
    let scene = vitro_record::synthetic::scene();
    let input = frames(&scene, 50, 14);
    record(&path, &input, &RecordOptions::default());
    let mut replay = Replay::open(&path).unwrap();
    let mut tracks = kml::Tracks::new();
    for f in replay.frames() {
        tracks.add(&f.unwrap());
    }
    assert_eq!(tracks.len(), 14);
    let mut doc = Vec::new();
    tracks.write(replay.scene(), &mut doc).unwrap();
    let doc = String::from_utf8(doc).unwrap();
    assert_eq!(
        doc,
        kml::export(&scene, &input),
        "the same document either way"
    );
    assert!(doc.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>"));

    let (parsed, counts) = parse(&doc);
    assert_eq!(counts["kml"], 1);
    assert_eq!(parsed.len(), 14);
    assert_eq!(counts["Placemark"], 14 + scene.places.len());
    assert_eq!(counts["Style"], 5);
    let g = scene.geo;
    for (whens, coords) in &parsed {
        assert_eq!(*whens, 50);
        assert_eq!(coords.len(), 50);
        for &[lon, lat, alt] in coords {
            // The synthetic town is 1 km across around the origin: within ~0.01 degrees.
            assert!((lat - g.lat0).abs() < 0.01, "lat {lat}");
            assert!((lon - g.lon0).abs() < 0.01, "lon {lon}");
            assert!((0.0..200.0).contains(&alt), "alt {alt}");
        }
    }
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn names_with_markup_stay_well_formed() {
    let mut scene = vitro_record::synthetic::scene();
    scene.name = "<Town> & \"co\"".into();
    scene.places.insert("a<b>&c".into(), [0.0; 3]);
    let mut f = vitro_record::synthetic::frame(&scene, 0, 2);
    f.entities[0].name = "x</name><y>".into();
    let doc = kml::export(&scene, [f]);
    let (tracks, _) = parse(&doc);
    assert_eq!(tracks.len(), 2);
    assert!(doc.contains("x&lt;/name&gt;&lt;y&gt;"));
}
