#![no_main]

use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;
use vitro_algo::planning::pddl::{Domain, parse_domain, parse_problem};

/// The domains problems are parsed against: the repository's own.
fn domains() -> &'static [Domain] {
    static DOMAINS: OnceLock<Vec<Domain>> = OnceLock::new();
    DOMAINS.get_or_init(|| {
        [
            include_str!("../../crates/vitro-cli/tests/pddl/switch-domain.pddl"),
            include_str!("../../data/planning/depot/domain.pddl"),
            include_str!("../../data/planning/dwr/domain.pddl"),
        ]
        .iter()
        .map(|text| parse_domain(text, "domain.pddl").expect("the fixture domains parse"))
        .collect()
    })
}

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        for domain in domains() {
            let _ = parse_problem(domain, text, "fuzz.pddl");
        }
    }
});
