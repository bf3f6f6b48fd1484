//! In vitro, honestly: an agent knows where another unit is only from its own sensors or
//! from that unit's position reports over the simulated radio. With the radio dead and
//! every camera cut to 40 m, the UAVs never learn where the truck is, and do not fly to
//! it; with the radio working they learn it through the truck's reports.

use vitro::entity::EntityId;
use vitro::time::SimTime;
use vitro_evac::EvacRun;
use vitro_evac::Mission;
use vitro_evac::agents::air::{AirRole, Aircraft};
use vitro_evac::scenario::ScenarioFile;
use vitro_tactical::scenario::EntityType;

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

/// The default mission (discrete level, seed 3) with every camera at 40 m, the UAVs
/// starting at the extraction point (1.5 km from the team by road) and the radio's loss
/// probability `loss`.
fn mission(loss: f64) -> EvacRun {
    let mut v = ScenarioFile::validate(SCENARIO).expect("the scenario");
    let f = &mut v.loaded.file;
    let far = f.places.extraction;
    for e in &mut f.entities {
        if matches!(
            e.kind,
            EntityType::Vidar | EntityType::Skeldar | EntityType::Procerus
        ) {
            e.start = Some(far);
        }
    }
    f.channel.loss = loss;
    f.sensors.air.range_m = 40.0;
    f.sensors.ground.range_m = 40.0;
    Mission::build(v, Some(3)).expect("builds")
}

/// The UAVs of a mission: id and controller.
fn aircraft(m: &EvacRun) -> Vec<(EntityId, &Aircraft)> {
    m.members
        .iter()
        .filter_map(|mem| {
            let a = m.sim.agent(mem.id)?.as_any().downcast_ref::<Aircraft>()?;
            Some((mem.id, a))
        })
        .collect()
}

/// Horizontal distance between two entities, metres (the umpire's view, for the test).
fn apart(m: &EvacRun, a: EntityId, b: EntityId) -> f64 {
    let (p, q) = (m.sim.env().pose(a).unwrap(), m.sim.env().pose(b).unwrap());
    libm::hypot(p.pos[0] - q.pos[0], p.pos[1] - q.pos[1])
}

#[test]
fn with_the_radio_dead_a_uav_never_learns_where_the_truck_is() {
    let mut dead = mission(1.0);
    let truck = dead.brief.truck;
    let uavs: Vec<EntityId> = aircraft(&dead).iter().map(|(id, _)| *id).collect();
    assert!(uavs.len() >= 3, "the scenario's UAVs: {uavs:?}");
    for &u in &uavs {
        assert!(
            apart(&dead, u, truck) > 300.0,
            "UAV {u:?} starts far from the truck"
        );
    }
    dead.advance(SimTime::from_secs(400));
    for (id, a) in aircraft(&dead) {
        assert!(
            a.known().last(truck).is_none(),
            "UAV {id:?} knows where the truck is without a radio or a camera that reaches it"
        );
        assert_eq!(
            a.known().reports,
            0,
            "UAV {id:?} heard a report over a dead radio"
        );
    }

    // The same mission with a working radio: every UAV hears the truck's reports, and its
    // estimate is where the truck is (within the distance the truck covers between two
    // reports).
    let mut live = mission(0.0);
    live.advance(SimTime::from_secs(400));
    let now = live.sim.now();
    let truth = live.sim.env().pose(truck).unwrap().pos;
    for (id, a) in aircraft(&live) {
        assert!(a.known().reports > 0, "UAV {id:?} heard no report");
        let at = a.known().estimate(truck, now).expect("a fresh report");
        let off = libm::hypot(at[0] - truth[0], at[1] - truth[1]);
        assert!(off < 80.0, "UAV {id:?} puts the truck {off:.0} m off");
    }
    // Knowing it, the scout and the cover UAVs fly to it; not knowing it, they never come
    // near (the Skeldar flies the patrol game's briefed checkpoints whatever it knows).
    let near = |m: &EvacRun| {
        aircraft(m)
            .iter()
            .filter(|(u, a)| a.role != AirRole::Patrol && apart(m, *u, truck) < 600.0)
            .count()
    };
    assert!(near(&live) >= 2, "with reports the UAVs cover the truck");
    assert_eq!(near(&dead), 0, "without them no UAV finds the truck");
}
