//! The batch runner of the demo scenario (patrolling cars), until the mission exists.

use std::collections::BTreeMap;
use vitro::prelude::SimTime;
use vitro_batch::{RunOutput, RunSettings, Runner, SeriesRow, Value};
use vitro_demo::config::DemoConfig;
use vitro_demo::{Metrics, Scenario};

/// Runs demo scenarios for `vitro batch`.
pub(crate) struct DemoRunner;

/// The demo's metrics as named values, in summary-column order.
fn metric_values(m: &Metrics) -> Vec<(&'static str, Value)> {
    let int = |x: u64| Value::Int(i64::try_from(x).unwrap_or(i64::MAX));
    vec![
        ("mean_idleness_s", Value::Float(m.mean_idleness_s)),
        ("max_idleness_s", Value::Float(m.max_idleness_s)),
        ("visits", int(m.visits)),
        ("decisions", int(m.decisions)),
        ("goals_reached", int(m.goals_reached)),
        ("yielded", int(m.yielded)),
        ("messages_sent", int(m.messages_sent)),
        ("messages_received", int(m.messages_received)),
        ("messages_lost", int(m.messages_lost)),
        ("messages_bounced", int(m.messages_bounced)),
        ("events", int(m.events)),
        ("sim_time_s", Value::Float(m.sim_time_s)),
        ("junctions", int(m.junctions as u64)),
        ("streets", int(m.streets as u64)),
        ("cars", int(m.cars as u64)),
        ("stop", Value::Text(m.stop.clone())),
        ("trace_hash", Value::Text(format!("{:016x}", m.trace_hash))),
    ]
}

/// The scenario table as a checked demo configuration.
fn config(scenario: &toml::Table) -> Result<DemoConfig, String> {
    let cfg: DemoConfig = toml::Value::Table(scenario.clone())
        .try_into()
        .map_err(|e: toml::de::Error| e.message().trim_end().to_owned())?;
    cfg.validate().map_err(|e| e.to_string())?;
    Ok(cfg)
}

impl Runner for DemoRunner {
    fn metric_names(&self, scenario: &toml::Table) -> Result<Vec<String>, String> {
        let s = Scenario::build(config(scenario)?).map_err(|e| e.to_string())?;
        Ok(metric_values(&s.metrics())
            .into_iter()
            .map(|(k, _)| k.to_owned())
            .collect())
    }

    fn run(
        &self,
        scenario: &toml::Table,
        seed: u64,
        settings: &RunSettings<'_>,
    ) -> Result<RunOutput, String> {
        let mut cfg = config(scenario)?;
        cfg.seed = seed;
        if let Some(end) = settings.end_s {
            cfg.end_s = end;
        }
        let mut s = Scenario::build(cfg).map_err(|e| e.to_string())?;
        let keep = settings.keep;
        let mut series = Vec::new();
        match keep.every_s.filter(|_| !keep.series.is_empty()) {
            None => {
                s.run().map_err(|e| e.to_string())?;
            }
            Some(every) => {
                // Sample at every, 2*every, ... (no drift: each time from its index) and at the end.
                for k in 1u64.. {
                    let t = SimTime::from_secs_f64(k as f64 * every).min(s.end());
                    let reason = s.run_to(t).map_err(|e| e.to_string())?;
                    let m = s.metrics();
                    let values: BTreeMap<String, Value> = metric_values(&m)
                        .into_iter()
                        .filter(|(name, _)| keep.series.iter().any(|k| k == name))
                        .map(|(name, v)| (name.to_owned(), v))
                        .collect();
                    series.push(SeriesRow {
                        t_s: m.sim_time_s,
                        values,
                    });
                    if t >= s.end() || reason != vitro::prelude::StopReason::Time {
                        break;
                    }
                }
            }
        }
        let metrics = metric_values(&s.metrics())
            .into_iter()
            .map(|(k, v)| (k.to_owned(), v))
            .collect();
        Ok(RunOutput { metrics, series })
    }

    fn scenario_file(
        &self,
        scenario: &toml::Table,
        seed: u64,
        end_s: Option<f64>,
        _dir: &std::path::Path,
    ) -> Result<String, String> {
        let mut t = scenario.clone();
        let seed =
            i64::try_from(seed).map_err(|_| format!("seed {seed} does not fit a TOML integer"))?;
        t.insert("seed".into(), toml::Value::Integer(seed));
        if let Some(end) = end_s {
            let old = t.get("end_s").and_then(toml::Value::as_float);
            t.insert(
                "end_s".into(),
                toml::Value::Float(old.map_or(end, |o| o.min(end))),
            );
        }
        toml::to_string(&t).map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vitro_batch::Keep;

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
        let out = DemoRunner.run(&scenario(), 5, &settings).unwrap();
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
        let again = DemoRunner.run(&scenario(), 5, &plain).unwrap();
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
        let err = DemoRunner.run(&s, 1, &settings).unwrap_err();
        assert!(err.contains("channel.loss"), "{err}");
        assert!(DemoRunner.metric_names(&s).is_err());
        assert_eq!(
            DemoRunner.metric_names(&scenario()).unwrap()[0],
            "mean_idleness_s"
        );
    }
}
