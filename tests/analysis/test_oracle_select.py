"""A claim names its oracle through the engine's capabilities: ``oracle = "@default"``
or ``oracle = { kind = "form-factor" }``, resolved before any run."""

import json

import pytest

from hrbench_analysis.claimfile import ClaimsFileError, load_claims, resolve_oracle
from hrbench_analysis.engine import get_capabilities
from hrbench_analysis.reproduce import main

CLAIMS = (open(__file__.replace("test_oracle_select.py", "data/small_claims.toml")).read()
          .replace('scene = "parallel"', 'scene = "parallel"\noracle = ORACLE'))


def claims_file(tmp_path, oracle):
    path = tmp_path / "c.toml"
    path.write_text(CLAIMS.replace("ORACLE", oracle))
    return path


def resolved(tmp_path, fake_hrbench, oracle):
    (claim,) = load_claims(claims_file(tmp_path, oracle))
    return resolve_oracle(claim, get_capabilities(str(fake_hrbench)))


def test_reference_kinds_resolve_on_hrbench(tmp_path, fake_hrbench):
    # The fake lists hrbench's names without kinds: the reference kinds apply.
    assert resolved(tmp_path, fake_hrbench, '"@default"') == ("garmann", None)
    assert resolved(tmp_path, fake_hrbench, '{ kind = "form-factor" }') == ("hanrahan", None)
    assert resolved(tmp_path, fake_hrbench, '"garmann"') == ("garmann", None)


def test_own_oracle_names_resolve_by_kind(tmp_path, fake_hrbench, monkeypatch):
    monkeypatch.setenv("FAKE_HRBENCH_CAPABILITIES", "own-oracles")
    assert resolved(tmp_path, fake_hrbench, '"@default"') == ("area-over-r", None)
    # Two oracles are of kind form-factor, one of them for 2D, the claim's dimension.
    assert resolved(tmp_path, fake_hrbench, '{ kind = "form-factor" }') == ("ff-disc", None)
    name, error = resolved(tmp_path, fake_hrbench, '{ kind = "radiosity" }')
    assert name is None
    assert error == ("the engine lists no oracle of kind 'radiosity' for 2D; its oracles: "
                     "area-over-r (geometric), ff-disc (form-factor), ff-exact (form-factor)")


def test_claim_runs_with_the_engines_own_oracle(tmp_path, fake_hrbench, monkeypatch, capsys):
    monkeypatch.setenv("FAKE_HRBENCH_CAPABILITIES", "own-oracles")
    log = tmp_path / "log"
    monkeypatch.setenv("FAKE_HRBENCH_LOG", str(log))
    results = tmp_path / "results"
    code = main(["--claims", str(claims_file(tmp_path, '{ kind = "form-factor" }')),
                 "--hrbench", str(fake_hrbench), "--results", str(results), "--no-pictures"])
    out, err = capsys.readouterr()
    assert code == 0, err
    runs = log.read_text().splitlines()
    assert runs and all("--oracle ff-disc" in line for line in runs)
    (claim,) = json.loads((results / "claims.json").read_text())["claims"]
    assert claim["verdict"] == "reproduced"


def test_unresolved_selector_is_an_error(tmp_path, fake_hrbench, monkeypatch, capsys):
    monkeypatch.setenv("FAKE_HRBENCH_CAPABILITIES", "own-oracles")
    code = main(["--claims", str(claims_file(tmp_path, '{ kind = "radiosity" }')),
                 "--hrbench", str(fake_hrbench), "--results", str(tmp_path / "r"),
                 "--no-pictures"])
    out, err = capsys.readouterr()
    assert code == 2
    assert "claim 'T-elements': the engine lists no oracle of kind 'radiosity'" in err


@pytest.mark.parametrize("oracle, message", [
    ('{ kind = 1 }', "key 'oracle' as a table must be { kind = WORD }"),
    ('{ name = "x" }', "key 'oracle' as a table must be { kind = WORD }"),
    ('"@best"', "names no selector"),
    ('3', "key 'oracle' must be a non-empty string"),
])
def test_bad_selectors(tmp_path, oracle, message):
    with pytest.raises(ClaimsFileError, match=message.replace("{", r"\{").replace("}", r"\}")):
        load_claims(claims_file(tmp_path, oracle))
