use super::*;
use crate::graph::Graph;
use crate::pursuit::{FullVisibility, HopRange};

fn load(name: &str) -> Graph {
    let path = format!("{}/../../data/graphs/{name}.edges", env!("CARGO_MANIFEST_DIR"));
    Graph::load(&path).unwrap()
}

fn mcts(b: u64) -> MoIsmcts {
    MoIsmcts::new(MoIsmctsConfig {
        budget: crate::pursuit::Budget::iterations(b),
        ..MoIsmctsConfig::default()
    })
}

#[test]
fn smoke() {
    let arena = Arena::new(load("petersen"), &FullVisibility).unwrap();
    let s = evaluate(&arena, 3, 4, 30, 1, &mut || Box::new(mcts(300)), &mut || {
        Box::new(ExactEvader::new(&arena, 3).unwrap())
    })
    .unwrap();
    println!("{s:?}");
    let g = load("grid4x4");
    let arena = Arena::new(g.clone(), &HopRange::new(&g, 1)).unwrap();
    let s = evaluate(&arena, 2, 4, 30, 1, &mut || Box::new(mcts(300)), &mut || {
        Box::new(ExactEvader::new(&arena, 2).unwrap())
    })
    .unwrap();
    println!("{s:?}");
}
