//! The batch runner of every mission is `vitro_mission::batch::MissionRunner`; this is the
//! runner of an experiment whose scenario names no registered mission.

use vitro_batch::{RunOutput, RunSettings, Runner};

/// The runner of an experiment whose scenario names no registered mission: every call
/// answers why.
pub(crate) struct NoMission(pub(crate) String);

impl Runner for NoMission {
    fn metric_names(&self, _: &toml::Table) -> Result<Vec<String>, String> {
        Err(self.0.clone())
    }

    fn run(&self, _: &toml::Table, _: u64, _: &RunSettings<'_>) -> Result<RunOutput, String> {
        Err(self.0.clone())
    }
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;
    use vitro_batch::{Keep, RunSettings, Runner};
    use vitro_mission::batch::MissionRunner;

    const DEMO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/demo.toml");

    fn runner() -> MissionRunner {
        MissionRunner {
            mission: &vitro_demo::PatrollingCars,
            path: PathBuf::from(DEMO),
        }
    }

    fn scenario() -> toml::Table {
        let src = include_str!("../../../../scenarios/demo.toml");
        toml::from_str(src).expect("the demo scenario parses")
    }

    #[test]
    fn runs_the_demo_and_samples_series() {
        let keep = Keep {
            metrics: vec![],
            series: vec!["visits".into(), "mean_idleness_s".into()],
            every_s: Some(250.0),
        };
        let settings = RunSettings {
            end_s: Some(600.0),
            keep: &keep,
        };
        let out = runner().run(&scenario(), 5, &settings).unwrap();
        let times: Vec<f64> = out.series.iter().map(|r| r.t_s).collect();
        assert_eq!(times, [250.0, 500.0, 600.0]);
        assert_eq!(out.series[0].values.len(), 2);
        assert_eq!(
            out.series[2].values["visits"], out.metrics["visits"],
            "the last sample is the end"
        );
        // Sampling does not change the run.
        let plain = RunSettings {
            end_s: Some(600.0),
            keep: &Keep::default(),
        };
        let again = runner().run(&scenario(), 5, &plain).unwrap();
        assert_eq!(again.metrics, out.metrics);
        assert!(again.series.is_empty());
    }

    #[test]
    fn bad_values_fail_the_run() {
        let mut s = scenario();
        s["channel"]
            .as_table_mut()
            .expect("a channel table")
            .insert("loss".into(), toml::Value::Float(1.5));
        let keep = Keep::default();
        let settings = RunSettings {
            end_s: None,
            keep: &keep,
        };
        let err = runner().run(&s, 1, &settings).unwrap_err();
        assert!(err.contains("channel.loss"), "{err}");
        assert!(runner().metric_names(&s).is_err());
        assert_eq!(
            runner().metric_names(&scenario()).unwrap()[0],
            "mean_idleness_s"
        );
    }
}
