//! The village instance (`data/patrol/village.*`): rebuilt from the town's street graph it
//! matches the committed files, it loads, and its convoys are what its comments say.

use std::path::Path;

use vitro_algo::patrol::{Instance, TargetPosition};

#[allow(dead_code)]
#[path = "../examples/patrol_village_data.rs"]
mod village_data;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data");

#[test]
fn the_committed_files_are_what_the_generator_builds() {
    let built = village_data::build(Path::new(&format!("{DATA}/town"))).unwrap();
    assert_eq!(built.len(), 3);
    for (name, text) in built {
        let committed = std::fs::read_to_string(format!("{DATA}/patrol/{name}")).unwrap();
        assert!(
            committed == text,
            "data/patrol/{name} differs from the generator's output"
        );
    }
}

#[test]
fn the_village_is_three_convoys_on_a_connected_town_and_two_units() {
    let village = Instance::load(format!("{DATA}/patrol/village.toml")).unwrap();
    let g = &village.graph;
    assert_eq!((g.node_count(), g.edge_count()), (117, 167));
    assert_eq!(g.components().len(), 1);
    assert_eq!(village.patrollers.len(), 2);
    assert_eq!(village.period().unwrap(), 48);
    let schedules: Vec<&Vec<usize>> = village
        .targets
        .iter()
        .map(|t| match &t.position {
            TargetPosition::Schedule(s) => s,
            TargetPosition::Static(_) => panic!("a convoy stands still"),
        })
        .collect();
    assert_eq!(schedules.len(), 3);
    // Every convoy waits at the depot (cell 62) and leaves it 16 steps after the previous one.
    let depot = 62;
    let departures: Vec<usize> = schedules
        .iter()
        .map(|s| {
            (0..48)
                .find(|&k| s[k] == depot && s[(k + 1) % 48] != depot)
                .unwrap()
        })
        .collect();
    for (i, &d) in departures.iter().enumerate() {
        let next = departures[(i + 1) % 3];
        assert_eq!((next + 48 - d) % 48, 16, "departures {departures:?}");
    }
    // Half the units' speed: every cell of a route is held for at least two steps.
    for s in &schedules {
        for k in 0..48 {
            if s[k] != s[(k + 1) % 48] {
                assert_eq!(s[(k + 47) % 48], s[k]);
            }
        }
    }
    for t in &village.targets {
        assert_eq!((t.value, t.deadline), (1.0, 8));
    }
}
