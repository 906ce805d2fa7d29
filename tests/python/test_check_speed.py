"""What makes `btgen check` fast must not change what it finds (issue 38, item 6; the numbers are
bench/check_corpus.py's): the mission XSD compiled without xmlschema's meta-schema check, the
validations and parsed files shared between the loads of one run."""

import glob
import os

import pytest
import xmlschema

from btgen.cli import main
from btgen.diagnostics import UserError
from btgen.frontend import xmlsource, xsd
from btgen.frontend.loader import load_mission
from conftest import ROOT


def _missions():
    """The shipped missions, a Nav2 tree with Nav2's models, the recorded load rules on both releases."""
    cases = [(p, "4.6.2", ()) for p in sorted(glob.glob(os.path.join(ROOT, "examples", "**", "*.xml"), recursive=True))]
    nav2 = os.path.join(ROOT, "tests", "real_files", "nav2")
    cases.append(
        (
            os.path.join(nav2, "navigate_to_pose_w_replanning_and_recovery.xml"),
            "4.6.2",
            (os.path.join(nav2, "nav2_tree_nodes.xml"),),
        )
    )
    both = sorted(glob.glob(os.path.join(ROOT, "tests", "conformance", "both-releases", "*.xml")))
    cases += [(p, v, ()) for p in both for v in ("4.6.2", "4.10.0")]
    for path, version, models in cases:
        try:
            mission = load_mission(path, models, btcpp=version)
        except UserError:
            continue
        yield mission


def test_every_mission_schema_passes_the_meta_schema():
    """`_compiled` leaves out xmlschema's check of the generated XSD against the XSD meta-schema:
    every distinct schema of the shipped and recorded missions passes it."""
    missions = list(_missions())
    assert any(m.nav2 for m in missions)
    texts = {xsd.mission_xsd(m, lenient=True, comment=False) for m in missions}
    assert len(texts) >= 5
    for text in texts:
        xmlschema.XMLSchema(text, validation="strict")  # raises on an error


def test_a_schema_without_the_meta_check_finds_the_same(tmp_path):
    """Each mission's files against another mission's schema (so that there are errors to find)."""
    missions = [m for m in _missions() if m.models][:6]
    found = 0
    for m1 in missions:
        text = xsd.mission_xsd(m1, lenient=True)
        strict, skip = xmlschema.XMLSchema(text), xmlschema.XMLSchema(text, validation="skip")
        for m2 in missions:
            src = xmlsource.read_source(m2.files[0])
            a = [str(d) for d in xsd._iter_diags(strict, src, src.root)]
            assert a == [str(d) for d in xsd._iter_diags(skip, src, src.root)]
            found += bool(a)
    assert found >= 6


def test_a_file_changed_between_two_runs_is_read_again(tmp_path, capsys):
    (tmp_path / "m.xml").write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="M">\n    <AlwaysSuccess/>\n  </BehaviorTree>\n</root>\n'
    )
    assert main(["check", str(tmp_path)]) == 0
    (tmp_path / "m.xml").write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="M">\n    <AlwaysSucess/>\n  </BehaviorTree>\n</root>\n'
    )
    assert main(["check", str(tmp_path)]) == 1
    assert "m.xml:3:5: error: unknown node `AlwaysSucess`" in capsys.readouterr().err


def test_shared_sources_are_bounded(tmp_path, monkeypatch):
    monkeypatch.setattr(xmlsource, "_SHARED_MAX_BYTES", 400)
    with xmlsource.shared_sources():
        for i in range(6):
            path = tmp_path / f"t{i}.xml"
            path.write_text(f'<root BTCPP_format="4"><BehaviorTree ID="T{i}"><AlwaysSuccess/></BehaviorTree></root>\n')
            first = xmlsource.read_source(str(path))
            assert xmlsource.read_source(str(path)) is first  # shared while it fits
        assert 1 <= len(xmlsource._SHARED) <= 400 // len(first.text)
    assert xmlsource._SHARED is None
    assert xmlsource.read_source(str(path)) is not xmlsource.read_source(str(path))  # outside: never


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_file_included_by_many_missions_gives_one_finding_each_place(tmp_path, capsys, jobs):
    (tmp_path / "lib.xml").write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="Lib">\n    <Sequence>\n      <AlwaysSuccess/>\n'
        '      <Script code="x := 1" bogus="1"/>\n    </Sequence>\n  </BehaviorTree>\n</root>\n'
    )
    for i in range(3):
        (tmp_path / f"m{i}.xml").write_text(
            f'<root BTCPP_format="4" main_tree_to_execute="M{i}">\n  <include path="lib.xml"/>\n'
            f'  <BehaviorTree ID="M{i}">\n    <SubTree ID="Lib"/>\n  </BehaviorTree>\n</root>\n'
        )
    assert main(["check", "-j", jobs, str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert err.count("lib.xml:5:29: error:") == 1, err


def test_validations_are_shared_and_bounded(tmp_path, monkeypatch):
    path = tmp_path / "m.xml"
    path.write_text('<root BTCPP_format="4"><Bogus/><BehaviorTree ID="T"><AlwaysSuccess/></BehaviorTree></root>\n')
    src = xmlsource.read_source(str(path))
    first = xsd.validate_structure(src)
    assert first and xsd.validate_structure(src) == first  # the same findings, from the cache
    monkeypatch.setattr(xsd, "_VALIDATED", type(xsd._VALIDATED)())
    monkeypatch.setattr(xsd, "_VALIDATED_MAX_DIAGS", len(first) - 1)
    assert xsd.validate_structure(src) == first and not xsd._VALIDATED  # too many to keep
    monkeypatch.setattr(xsd, "_VALIDATED_MAX_DIAGS", 64)
    monkeypatch.setattr(xsd, "_VALIDATED_MAX", 2)
    for i in range(4):
        path.write_text(path.read_text() + " " * i)
        xsd.validate_structure(xmlsource.read_source(str(path)))
    assert len(xsd._VALIDATED) == 2
