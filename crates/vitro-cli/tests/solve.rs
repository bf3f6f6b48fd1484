//! `vitro solve cops`: the reference graphs through the command line, and bad input.

mod common;

use common::{repo, vitro};

#[test]
fn every_reference_graph_gets_its_stated_cop_number() {
    let dir = repo().join("data/graphs");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("data/graphs") {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|e| e != "edges") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("readable");
        let stated: usize = text
            .lines()
            .next()
            .and_then(|l| l.rsplit("cop number").next())
            .and_then(|s| s.trim().parse().ok())
            .expect("the first line states the cop number");
        let p = path.to_string_lossy().into_owned();
        let (code, out, err) = vitro(&["solve", "cops", &p, "--json"]);
        assert_eq!(code, 0, "{p}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
        assert_eq!(v["cop_number"].as_u64(), Some(stated as u64), "{p}");
        n += 1;
    }
    assert_eq!(n, 10, "all ten reference graphs were tried");
}

#[test]
fn malformed_graphs_are_bad_input_with_a_place() {
    let tmp = std::env::temp_dir().join(format!("vitro-cops-{}.edges", std::process::id()));
    std::fs::write(&tmp, "# a graph\n0 1\n1 x\n").expect("temp file");
    let p = tmp.to_string_lossy().into_owned();
    let (code, _, err) = vitro(&["solve", "cops", &p]);
    let _ = std::fs::remove_file(&tmp);
    assert_eq!(code, 2);
    assert!(err.contains(&format!("{p}:3:3")), "{err}");
    let (code, _, err) = vitro(&["solve", "cops", "no/such.edges"]);
    assert_eq!(code, 2);
    assert!(err.contains("no/such.edges"), "{err}");
}
