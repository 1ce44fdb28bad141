"""Bad input raises a Python exception with the CLI's one-line message."""

import numpy as np
import pytest

import conftrack


def cli_message(cli, *args):
    done = cli(*args, check=False)
    assert done.returncode == 1, done.stderr
    line = done.stderr.strip().splitlines()[-1]
    prefix = "conftrack: error: "
    assert line.startswith(prefix)
    return line[len(prefix):]


def test_missing_folder_is_file_not_found(cli, tmp_path):
    missing = tmp_path / "nowhere"
    with pytest.raises(FileNotFoundError) as e:
        conftrack.read_event(missing, 1)
    assert str(e.value) == f"{missing}: no such file (nor with .gz)" or \
        str(missing) in str(e.value)
    assert "\n" not in str(e.value)


def test_missing_event_file_same_message_as_cli(cli, tmp_path):
    cli("simulate", "--sample", "muons", "-n", "1", "-o", tmp_path / "ev")
    (tmp_path / "ev" / "event000000001-hits.csv").rename(
        tmp_path / "ev" / "event000000001-hits.txt")
    (tmp_path / "ev" / "event000000002-hits.csv").write_text(
        "hit_id,x,y,z,volume_id,layer_id,module_id\n")
    with pytest.raises(FileNotFoundError) as e:
        conftrack.read_event(tmp_path / "ev", 1)
    assert "event000000001-hits.csv: no such file (nor with .gz)" in str(e.value)


def test_unknown_detector_same_message_as_cli(cli, tmp_path):
    message = cli_message(cli, "detector", "show", "nosuchdetector")
    with pytest.raises(FileNotFoundError) as e:
        conftrack.Detector("nosuchdetector")
    assert str(e.value) == message


def test_corrupt_hits_file_same_message_as_cli(cli, tmp_path):
    events = tmp_path / "events"
    events.mkdir()
    (events / "event000000001-hits.csv").write_text(
        "hit_id,x,y,z,volume_id,layer_id,module_id\n"
        "1,31.0,0.0,10.0,1,2,0\n"
        "2,nan,0.0,10.0,1,2,0\n")
    message = cli_message(cli, "reconstruct", "-i", events,
                          "-o", tmp_path / "out")
    with pytest.raises(ValueError) as e:
        conftrack.read_hits(events / "event000000001-hits.csv", "clicdet")
    assert str(e.value) == message
    assert "not finite" in message or "not a number" in message


def hits_of_one_muon():
    return conftrack.simulate("muons", events=1, seed=2)[0].hits


def test_bad_hit_tables_raise_value_error():
    hits = hits_of_one_muon()
    with pytest.raises(ValueError, match="hits: missing column 'z'"):
        conftrack.reconstruct(hits.drop(columns="z"))
    bad = hits.copy()
    bad.loc[2, "x"] = np.inf
    with pytest.raises(ValueError, match=r"hits row 2: column 'x': .*not finite"):
        conftrack.reconstruct(bad)
    off = hits.copy()
    off.loc[0, "z"] += 500.0
    with pytest.raises(ValueError, match="hits row 0: .*is not on the layer"):
        conftrack.reconstruct(off)
    twice = hits.copy()
    twice.loc[3, "hit_id"] = twice.hit_id[1]
    with pytest.raises(ValueError, match="duplicate hit_id"):
        conftrack.reconstruct(twice)
    negative = hits.copy()
    negative.loc[0, "module_id"] = -1
    with pytest.raises(ValueError, match="module_id"):
        conftrack.reconstruct(negative)
    wrong = hits.copy()
    wrong.loc[0, "volume_id"] = 999
    with pytest.raises(ValueError, match=r"\(999, .*\) is not a layer"):
        conftrack.reconstruct(wrong)


def test_bad_arguments_name_the_key():
    with pytest.raises(ValueError, match="^events: must be >= 0"):
        conftrack.simulate("muons", events=-1)
    with pytest.raises(TypeError, match="^seed: "):
        conftrack.simulate("muons", seed="one")
    with pytest.raises(ValueError, match="no_such_key"):
        conftrack.simulate("muons", no_such_key=3)
    with pytest.raises(TypeError, match="^hits: expected a pandas DataFrame"):
        conftrack.reconstruct("hits.csv")
    with pytest.raises(TypeError, match="^threads: "):
        conftrack.reconstruct_many([], threads=1.5)
    with pytest.raises(FileNotFoundError, match="chain 'nochain'"):
        conftrack.reconstruct(hits_of_one_muon(), chain="nochain")
    with pytest.raises(ValueError, match="^evaluate: 1 events but 0 results"):
        conftrack.evaluate(conftrack.simulate("muons"), [])


def test_reconstruct_many_names_the_bad_event():
    hits = hits_of_one_muon()
    bad = hits.copy()
    bad.loc[1, "y"] = np.nan
    with pytest.raises(ValueError,
                       match=r"^events\[1\]: hits row 1: column 'y'"):
        conftrack.reconstruct_many([hits, bad], threads=2)
