"""vitro.run, vitro.batch and vitro.load_results against the `vitro` command."""
import json
import subprocess

import pytest

import vitro


def cli_json(vitro_bin, root, *args):
    out = subprocess.run(
        [str(vitro_bin), "run", *args, "--json"], cwd=root, capture_output=True, text=True
    )
    assert out.returncode in (0, 4), out.stderr  # 4: the mission failed (a verdict, not an error)
    return json.loads(out.stdout)


def test_evacuation_seed_42_has_the_commands_trace_hash(vitro_bin, root, monkeypatch):
    monkeypatch.chdir(root)
    py = vitro.run("scenarios/evacuation.toml", seed=42)
    cli = cli_json(vitro_bin, root, "scenarios/evacuation.toml", "--seed", "42")
    assert py["trace_hash"] == cli["trace_hash"]
    wall = {"wall_time_s", "events_per_wall_s", "sim_s_per_wall_s"}
    assert {k: v for k, v in py.items() if k not in wall} == {
        k: v for k, v in cli.items() if k not in wall
    }


def test_until_fidelity_and_overrides_are_the_commands(vitro_bin, root):
    scenario = str(root / "scenarios/evacuation.toml")
    py = vitro.run(scenario, seed=7, until=120, fidelity="discrete")
    cli = cli_json(vitro_bin, root, scenario, "--seed", "7", "--until", "120", "--fidelity", "discrete")
    assert py["trace_hash"] == cli["trace_hash"] and py["sim_time_s"] == 120.0
    demo = str(root / "scenarios/demo.toml")
    plain = vitro.run(demo, seed=1, until=120)
    lossy = vitro.run(demo, seed=1, until=120, overrides={"channel.loss": 0.9})
    assert plain["trace_hash"] != lossy["trace_hash"]
    assert lossy["messages_lost"] > plain["messages_lost"]


def test_a_bad_scenario_raises_with_file_line_and_column(tmp_path, vitro_bin):
    bad = tmp_path / "bad.toml"
    bad.write_text('kind = "evacuaton"\nseed = 1\n')
    with pytest.raises(vitro.InputError) as e:
        vitro.run(bad)
    assert str(e.value) == f'{bad}:1:8: "evacuaton" is not a kind of scenario (expected one of: evacuation, demo, surveillance, traffic)'
    assert isinstance(e.value, ValueError)
    # The same message as the command's, which exits 2 on it.
    out = subprocess.run([str(vitro_bin), "run", str(bad)], capture_output=True, text=True)
    assert out.returncode == 2 and out.stderr.strip() == f"error: {e.value}"


def test_a_mission_error_is_located_in_the_file(tmp_path, root):
    text = (root / "scenarios/evacuation.toml").read_text()
    assert "period_s = 1.0" in text
    bad = tmp_path / "evac.toml"
    bad.write_text(text.replace("period_s = 1.0", "period_s = -1.0").replace('"../data/', f'"{root}/data/'))
    with pytest.raises(vitro.InputError) as e:
        vitro.run(bad, until=10)
    line = text.splitlines().index(next(l for l in text.splitlines() if l.startswith("period_s = 1.0"))) + 1
    assert f"{bad}:{line}:" in str(e.value), str(e.value)


def test_bad_arguments_are_input_errors(root):
    demo = root / "scenarios/demo.toml"
    with pytest.raises(vitro.InputError, match="--until -1"):
        vitro.run(demo, until=-1)
    with pytest.raises(vitro.InputError, match="seed"):
        vitro.run(demo, seed=-3)
    with pytest.raises(vitro.InputError, match="override channel.los: unknown scenario key"):
        vitro.run(demo, overrides={"channel.los": 0.5})
    with pytest.raises(vitro.InputError, match="cannot read scenario"):
        vitro.run(root / "no-such.toml")


SMALL = """
name = "small"
scenario = "{root}/scenarios/demo.toml"
seed = 5
replicates = 2
end_s = 300.0
[parameters]
"channel.loss" = [0.0, 0.5]
[keep]
metrics = ["visits", "messages_lost", "trace_hash"]
series = ["visits"]
every_s = 100.0
"""


def test_batch_and_load_results(tmp_path, root):
    exp = tmp_path / "small.toml"
    exp.write_text(SMALL.format(root=root))
    out = tmp_path / "res"
    report = vitro.batch(exp, out, jobs=2)
    assert report["ran"] == report["planned"] > 0
    summary = vitro.load_results(out)
    assert len(summary) == report["planned"]
    assert list(summary["run"]) == sorted(summary["run"])
    assert {"run", "point", "replicate", "seed", "status", "wall_s"} <= set(summary.columns)
    assert (summary["status"] == "ok").all()
    series = vitro.load_results(out, "series")
    assert list(series.columns) == ["run", "t_s", "visits"]
    assert sorted(set(series["t_s"])) == [100.0, 200.0, 300.0]
    # Each run's hash is the one `vitro.run` gives for its seed and loss.
    row = summary.iloc[-1]
    again = vitro.run(root / "scenarios/demo.toml", seed=int(row["seed"]), until=300,
                      overrides={"channel.loss": float(row["channel.loss"])})
    assert again["trace_hash"] == row["trace_hash"]
    with pytest.raises(vitro.InputError, match="no such table"):
        vitro.load_results(tmp_path)


def test_a_bad_experiment_raises_input_error(tmp_path):
    exp = tmp_path / "exp.toml"
    exp.write_text("name = 3\n")
    with pytest.raises(vitro.InputError, match="invalid experiment"):
        vitro.batch(exp, tmp_path / "out")
