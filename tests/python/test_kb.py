"""The environment knowledge base: linter, loader, limits shared with the C++ reader."""

from __future__ import annotations

import os
import random
import re
from pathlib import Path

import pytest
import xmlschema

from btgen.cli import main
from btgen.diagnostics import Loc, UserError
from btgen.kb import lint as kb

ROOT = Path(__file__).resolve().parents[2]
BAD = ROOT / "tests" / "bad_kb"
SHIPPED = "data/environmentKnowledgeBaseInput.dat"
SHIPPED_INI = "data/environmentKnowledgeBaseConfiguration.ini"
MINIMAL = "tests/bad_kb/ok_minimal.dat"


@pytest.fixture(autouse=True)
def _at_root(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)  # paths in diagnostics are as given: relative to the repository


def _lint_args(name: str) -> list[str]:
    """.dat files alone; .ini and .xml files together with the minimal valid base."""
    path = f"tests/bad_kb/{name}"
    if name.endswith(".ini"):
        return ["lint-kb", MINIMAL, "--config", path]
    if name.endswith(".xml"):
        return ["lint-kb", MINIMAL, "--mission", path]
    return ["lint-kb", path]


CASES = sorted(p.name for p in BAD.iterdir() if p.suffix in (".dat", ".ini", ".xml"))


@pytest.mark.parametrize("name", CASES)
def test_bad_input_gives_exact_diagnostics(name: str, capsys: pytest.CaptureFixture[str]) -> None:
    expected = (BAD / name).with_suffix(".stderr").read_text(encoding="utf-8")
    status = main(_lint_args(name))
    captured = capsys.readouterr()
    assert captured.err == expected
    assert captured.out == ""
    assert status == (1 if ": error: " in expected else 0)


def test_every_case_has_its_expected_output() -> None:
    stems = {p.stem for p in BAD.iterdir()}
    for stem in stems:
        assert (BAD / f"{stem}.stderr").exists(), stem
        assert any((BAD / f"{stem}{ext}").exists() for ext in (".dat", ".ini", ".xml")), stem
    assert len(CASES) >= 40


def test_document_mistakes_are_covered() -> None:
    """Each mistake of D5.4.2's file has a case of its own."""
    text = {p.stem: p.read_text(encoding="utf-8") for p in BAD.glob("*.stderr")}
    assert (
        "unknown key `postGestureMessageenglish` (did you mean `postGestureMessageEnglish`?" in text["misspelled_key"]
    )
    assert "write `robotLocationPose`" in text["robot_location_renamed"]
    assert "is a placeholder, not a message: `No message in isiZulu`" in text["placeholder_message"]
    assert "the tour count is 3 but 2 location ids follow (1 2)" in text["tour_count_off_by_one"]


# ----- The shipped base ---------------------------------------------------------


ISIZULU_PLACEHOLDER_LINES = [14, 17, 26, 29, 38, 41, 50, 53, 62, 65]


def test_shipped_base_has_only_the_documented_warnings() -> None:
    diags = kb.lint_kb(SHIPPED, config_path=SHIPPED_INI)
    assert [d.severity for d in diags] == ["warning"] * 10
    assert [d.loc.line for d in diags] == ISIZULU_PLACEHOLDER_LINES
    assert all(
        re.fullmatch(
            r"`(pre|post)GestureMessageIsiZulu` of location [1-5] is a placeholder, "
            r"not a message: `No message in isiZulu` \(the robot would say it\)",
            d.message,
        )
        for d in diags
    )
    readme = (ROOT / "data" / "README.md").read_text(encoding="utf-8")
    assert "prints these ten warnings and no others" in readme


def test_shipped_base_through_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["lint-kb", SHIPPED, "--config", SHIPPED_INI]) == 0
    assert capsys.readouterr().err.count(": warning: ") == 10


def test_load_shipped_base() -> None:
    base = kb.load_kb(SHIPPED)
    assert [loc.id for loc in base.locations] == [1, 2, 3, 4, 5]
    assert base.tour == (1, 4, 3, 2, 5)
    assert [loc.id for loc in base.tour_locations()] == [1, 4, 3, 2, 5]
    roomba = base.location(4)
    assert roomba is not None
    assert roomba.description == "Roomba"
    assert roomba.pose == kb.Pose(5.0, 3.9, 110.0)
    assert roomba.gesture_target == kb.Point3(6.8, 4.8, 0.82)
    assert roomba.pre_gesture == kb.Messages("This is the Roomba", "No message in isiZulu", "Iyi yitwa rumba")
    assert roomba.post_gesture.english == "We use it for teaching mobile robotics"
    assert roomba.post_gesture.in_language("Kinyarwanda") == "Tuyikoresha mukwigisha mobile robotikisi"
    assert roomba.cultural_knowledge == ("DeicticShape",)
    assert roomba.loc == Loc(SHIPPED, 46, 1)
    start = base.location(1)
    assert start is not None and start.cultural_knowledge == ("SymbolicShapeRespect", "BowExtentRespect")
    assert start.pre_gesture.english == "Welcome to the robotics lab at Carnegie Mellon University Africa"
    assert base.location(6) is None
    assert len(base.warnings) == 10
    assert sorted(kb.iter_placeholders(base)) == sorted(
        (i, f"{phase}GestureMessageIsiZulu") for i in range(1, 6) for phase in ("pre", "post")
    )


def test_load_kb_raises_user_error_with_every_problem() -> None:
    with pytest.raises(UserError) as info:
        kb.load_kb("tests/bad_kb/wrong_value_count.dat")
    assert [str(d) for d in info.value.diagnostics] == (BAD / "wrong_value_count.stderr").read_text(
        encoding="utf-8"
    ).splitlines()


def test_load_config() -> None:
    config = kb.load_config(SHIPPED_INI)
    assert config == kb.KbConfiguration(
        SHIPPED_INI,
        "environmentKnowledgeBaseInput.dat",
        os.path.join("data", "environmentKnowledgeBaseInput.dat"),
        False,
    )
    assert kb.load_config("tests/bad_kb/config_ok.ini").verbose_mode is True
    with pytest.raises(UserError):
        kb.load_config("tests/bad_kb/config_equals.ini")


# ----- Format details ------------------------------------------------------------


def _write(tmp_path: Path, data: bytes, name: str = "kb.dat") -> str:
    path = tmp_path / name
    path.write_bytes(data)
    return str(path)


def _minimal_bytes() -> bytes:
    return (BAD / "ok_minimal.dat").read_bytes()


def test_crlf_bom_tabs_and_commas_are_accepted(tmp_path: Path) -> None:
    text = _minimal_bytes().decode()
    text = text.replace("2 3.2 8.4 0.82", "2\t3.2, 8.4 ,0.82").replace(
        "tourSpecification 2 1 2", "tourSpecification 2, 1,2"
    )
    path = _write(tmp_path, b"\xef\xbb\xbf" + text.replace("\n", "\r\n").encode())
    assert kb.lint_kb(path) == []
    base = kb.load_kb(path)
    assert base.tour == (1, 2)
    loc2 = base.location(2)
    assert loc2 is not None and loc2.gesture_target == kb.Point3(3.2, 8.4, 0.82)


def test_text_keeps_inner_blanks_quotes_and_hashes(tmp_path: Path) -> None:
    text = _minimal_bytes().decode().replace("1 Welcome to the lab", '1 "Welcome"  to the   lab # 1, ok  \t')
    base = kb.load_kb(_write(tmp_path, text.encode()))
    loc1 = base.location(1)
    assert loc1 is not None and loc1.pre_gesture.english == '"Welcome"  to the   lab # 1, ok'


def test_number_forms(tmp_path: Path) -> None:
    text = _minimal_bytes().decode().replace("1 0.5 1.0 90", "1 .5 +1. -1000000")
    loc1 = kb.load_kb(_write(tmp_path, text.encode())).location(1)
    assert loc1 is not None and loc1.pose == kb.Pose(0.5, 1.0, -1000000.0)


def test_text_limit_is_inclusive_and_in_bytes(tmp_path: Path) -> None:
    at_limit = "\u00e9" * (kb.KB_MAX_TEXT_BYTES // 2) + "a"  # 255 bytes, 128 characters
    assert len(at_limit.encode()) == kb.KB_MAX_TEXT_BYTES
    text = _minimal_bytes().decode().replace("1 Welcome to the lab", f"1 {at_limit}")
    assert kb.lint_kb(_write(tmp_path, text.encode())) == []


def test_missing_file_and_directory() -> None:
    assert [str(d) for d in kb.lint_kb("tests/bad_kb/no_such.dat")] == [
        "tests/bad_kb/no_such.dat:1:1: error: cannot read file: No such file or directory"
    ]
    assert [str(d) for d in kb.lint_kb("tests/bad_kb")] == [
        "tests/bad_kb:1:1: error: is a directory, not a knowledge base file"
    ]


def test_file_too_big(tmp_path: Path) -> None:
    path = _write(tmp_path, b"#" * (kb.KB_MAX_FILE_BYTES + 1))
    assert [d.message for d in kb.lint_kb(path)] == [
        f"file is {kb.KB_MAX_FILE_BYTES + 1} bytes; knowledge base files are limited to 131072 bytes"
    ]
    assert kb.lint_kb(_write(tmp_path, b"#" * kb.KB_MAX_FILE_BYTES, "at_limit.dat"))[0].message.startswith(
        "the knowledge base is empty"
    )


def test_every_bad_utf8_line_is_reported(tmp_path: Path) -> None:
    data = b"# caf\xe9\nrobotLocationDescription 1 ok\n# \xc3\n# \xed\xa0\x80 surrogate\n"
    assert [str(d) for d in kb.lint_kb(_write(tmp_path, data))] == [
        f"{tmp_path}/kb.dat:1:6: error: invalid UTF-8 byte 0xE9; save the file as UTF-8",
        f"{tmp_path}/kb.dat:3:3: error: invalid UTF-8 byte 0xC3; save the file as UTF-8",
        f"{tmp_path}/kb.dat:4:3: error: invalid UTF-8 byte 0xED; save the file as UTF-8",
    ]


def test_lone_carriage_return_is_a_control_character(tmp_path: Path) -> None:
    data = _minimal_bytes().replace(b"1 Welcome to the lab", b"1 Welcome\rto the lab")
    assert [d.message for d in kb.lint_kb(_write(tmp_path, data))] == ["control character U+000D is not allowed"]


def test_config_must_be_readable(tmp_path: Path) -> None:
    diags = kb.lint_kb(MINIMAL, config_path=str(tmp_path / "none.ini"))
    assert [str(d) for d in diags] == [f"{tmp_path}/none.ini:1:1: error: cannot read file: No such file or directory"]


# ----- Schema and limits ------------------------------------------------------------


def test_schema_keys_match_the_linter_tables() -> None:
    assert kb.schema_keys() == (*kb.LOCATION_KEYS, kb.TOUR_KEY)
    assert set(kb.LOCATION_KEYS) == {*kb.TEXT_KEYS, *kb.POINT_KEYS, kb.CULTURAL_KEY}
    assert len(kb.LOCATION_KEYS) == 10


def _header_limits() -> dict[str, str]:
    text = (ROOT / "runtime" / "include" / "btgen" / "kb_limits.hpp").read_text(encoding="utf-8")
    return dict(re.findall(r"inline constexpr \w+(?:::\w+)? (k\w+) = ([^;]+);", text))


def test_limits_agree_with_the_cpp_header() -> None:
    header = _header_limits()
    python = {
        "kMaxFileBytes": kb.KB_MAX_FILE_BYTES,
        "kMaxTextBytes": kb.KB_MAX_TEXT_BYTES,
        "kMaxCulturalKeys": kb.KB_MAX_CULTURAL_KEYS,
        "kMaxCulturalKeyBytes": kb.KB_MAX_CULTURAL_KEY_BYTES,
        "kMaxTourLocations": kb.KB_MAX_TOUR_LOCATIONS,
        "kMaxLocationId": kb.KB_MAX_LOCATION_ID,
        "kMaxAbsCoordinate": kb.KB_MAX_ABS_COORDINATE,
    }
    assert set(header) == set(python)
    for name, value in python.items():
        assert float(header[name].rstrip("uU")) == value, name


def test_limits_agree_with_the_schema() -> None:
    schema = kb.kb_schema()
    types = schema.types

    def facet(type_name: str, tag: str) -> str:
        return types[type_name].get_facet(f"{{http://www.w3.org/2001/XMLSchema}}{tag}").value

    assert int(facet("LocationId", "maxInclusive")) == kb.KB_MAX_LOCATION_ID
    assert float(facet("Coordinate", "maxInclusive")) == kb.KB_MAX_ABS_COORDINATE
    assert float(facet("Coordinate", "minInclusive")) == -kb.KB_MAX_ABS_COORDINATE
    assert int(facet("TourCount", "maxInclusive")) == kb.KB_MAX_TOUR_LOCATIONS
    assert int(facet("CulturalKey", "maxLength")) == kb.KB_MAX_CULTURAL_KEY_BYTES
    cultural = types["CulturalKnowledgeEntry"].content
    tour = types["TourSpecification"].content
    assert [e.max_occurs for e in cultural.iter_elements()] == [1, kb.KB_MAX_CULTURAL_KEYS]
    assert [e.max_occurs for e in tour.iter_elements()] == [1, kb.KB_MAX_TOUR_LOCATIONS]
    assert isinstance(schema, xmlschema.XMLSchema10)


# ----- Robustness ----------------------------------------------------------------------


def test_mutated_bases_give_diagnostics_never_exceptions(tmp_path: Path) -> None:
    """A small fuzz: random edits of a valid base must lint without raising."""
    rng = random.Random(20250322)
    original = _minimal_bytes()
    alphabet = [
        b" ",
        b"\t",
        b",",
        b"\n",
        b"#",
        b"0",
        b"1",
        b"9",
        b"-",
        b".",
        b"e",
        b"x",
        b"\xc3",
        b"\xa9",
        b"\x00",
        b"\r",
        b"tourSpecification 1 1\n",
        b"gestureTarget 1 1 2 3\n",
    ]
    path = tmp_path / "fuzz.dat"
    for _ in range(300):
        data = bytearray(original)
        for _ in range(rng.randint(1, 4)):
            i = rng.randrange(len(data))
            op = rng.random()
            if op < 0.4:
                del data[i : i + rng.randint(1, 12)]
            elif op < 0.8:
                data[i:i] = rng.choice(alphabet)
            else:
                data[i] = rng.randrange(256)
        path.write_bytes(bytes(data))
        diags = kb.lint_kb(str(path))
        for d in diags:
            assert d.loc.path == str(path) and d.loc.line >= 1 and d.loc.col >= 1
            assert "schema" not in d.message, d  # every schema reason is translated
        if not any(d.severity == "error" for d in diags):
            kb.load_kb(str(path))  # a base without errors always loads


def test_config_naming_a_fifo_says_what_it_is(tmp_path: Path) -> None:
    # (it said "not found", and reading it would wait for a writer forever)
    os.mkfifo(tmp_path / "kb.dat")
    (tmp_path / "c.ini").write_text("knowledgeBase kb.dat\n", encoding="utf-8")
    assert [str(d) for d in kb.lint_kb(MINIMAL, config_path=str(tmp_path / "c.ini"))] == [
        f"{tmp_path}/c.ini:1:15: error: knowledge base file `kb.dat` is not a regular file (looked for "
        f"`{tmp_path}/kb.dat`; the name is relative to the configuration file's folder)"
    ]
