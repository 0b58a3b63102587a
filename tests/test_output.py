"""Issue 35, "Output": a file's name reaches every report, and a name may hold any character but
/ and NUL. Control characters in names and messages are escaped in every format (text, GitHub,
JUnit, SARIF, GitLab, the summary, --explain-*, the one-line errors), the JSON report keeps the
real name; a launch file ros2 launch cannot decode is an error (test_launch_encodings.py)."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from urllib.parse import unquote

import pytest
from conftest import new_package, run_pkgforge
from lxml import etree

SCHEMAS = Path(__file__).parent / "schemas"
# what no report may print: C0 controls but the newline that ends a line, DEL, C1 controls
RAW_CONTROL = re.compile("[\x00-\x09\x0b-\x1f\x7f-\x9f]")
BROKEN_PY = "def generate_launch_description(:\n"  # a syntax error: PF301 names the file
TITLE = "title\x1b]0;pwned\x07.launch.py"  # OSC 0: sets the terminal's title
CLEAR = "clear\x1b[2J.launch.py"  # CSI 2J: clears the screen
FORGED = "x\n::error file=README.md,line=1::forged.launch.py"  # a GitHub annotation of its own
CONTROL = "ctl\x01.launch.xml"  # XML 1.0 cannot hold \x01, not even as &#1;
NOT_UTF8 = b"bad\xff.launch.py"  # a name whose bytes are not UTF-8 (os.fsdecode: '\udcff')


@pytest.fixture(scope="module")
def hostile(tmp_path_factory) -> Path:
    """A workspace whose package has launch files with hostile names, each failing to load."""
    workspace = tmp_path_factory.mktemp("names")
    (workspace / "src").mkdir()
    launch = new_package(workspace, "names_description") / "launch"
    for name in (TITLE, CLEAR, FORGED):
        (launch / name).write_text(BROKEN_PY)
    (launch / CONTROL).write_text("<launch><oops/></launch>\n")
    with open(os.path.join(os.fsencode(launch), NOT_UTF8), "w") as handle:
        handle.write(BROKEN_PY)
    return workspace


def report(workspace: Path, fmt: str, *args: str) -> str:
    result = run_pkgforge("verify", "--format", fmt, *args, cwd=workspace)
    assert result.returncode == 1, result.stdout + result.stderr  # the five PF301, no internal error
    assert result.stderr == "" or fmt != "text", result.stderr
    return result.stdout


def test_text_report_escapes_control_characters_in_names(hostile):
    text = report(hostile, "text")
    assert not RAW_CONTROL.search(text), [line for line in text.splitlines() if RAW_CONTROL.search(line)]
    lines = text.splitlines()
    assert len(lines) == 2 * 5 + 1  # each diagnostic its line and its hint, then the summary
    assert (
        "src/names_description/launch/title\\x1b]0;pwned\\x07.launch.py:1: PF301 [error] loading "
        "title\\x1b]0;pwned\\x07.launch.py failed: SyntaxError: invalid syntax "
        "(title\\x1b]0;pwned\\x07.launch.py, line 1) (launch-load-error)"
    ) in lines
    assert any(
        line.startswith("src/names_description/launch/clear\\x1b[2J.launch.py:1: PF301") for line in lines
    )
    forged = "src/names_description/launch/x\\n::error file=README.md,line=1::forged.launch.py:1: PF301"
    assert any(line.startswith(forged) for line in lines)
    assert any(line.startswith("src/names_description/launch/bad\\xff.launch.py:1: PF301") for line in lines)
    assert lines[-1].startswith("5 errors, 0 warnings, 0 infos in 1 packages")


def test_github_annotations_cannot_be_forged_by_a_file_name(hostile):
    lines = report(hostile, "github").splitlines()
    assert not any(RAW_CONTROL.search(line) for line in lines)
    annotations = lines[:-1]
    assert len(annotations) == 5
    assert all(line.startswith("::error file=src/names_description/launch/") for line in annotations)
    assert not any(line.startswith("::error file=README.md") for line in lines)
    # a property escapes : and , as GitHub documents; the message keeps them
    assert (
        "::error file=src/names_description/launch/x\\n%3A%3Aerror file=README.md%2Cline=1%3A%3A"
        "forged.launch.py,line=1,title=PF301 launch-load-error::loading x\\n::error file=README.md,"
        "line=1::forged.launch.py failed: "
    ) in "\n".join(annotations)


def test_junit_report_with_a_control_character_in_a_name(hostile, tmp_path):
    """Case 16: lxml refused the name (internal error, exit 2, no report)."""
    text = report(hostile, "junit")
    assert not RAW_CONTROL.search(text.replace("\n", ""))
    document = etree.fromstring(text.encode())
    etree.XMLSchema(etree.parse(str(SCHEMAS / "junit.xsd"))).assertValid(document)
    failure = document.find(".//testcase[@name='PF301 launch-load-error']/failure")
    assert failure is not None
    assert (
        "src/names_description/launch/ctl\\x01.launch.xml:1: loading ctl\\x01.launch.xml failed"
        in failure.text
    )
    assert "src/names_description/launch/title\\x1b]0;pwned\\x07.launch.py:1:" in failure.text
    # and --junit-xml beside another format, the way CI asks for it
    output = tmp_path / "junit.xml"
    result = run_pkgforge("verify", "--format", "json", "--junit-xml", output, cwd=hostile)
    assert result.returncode == 1, result.stderr
    etree.parse(str(output))


def test_sarif_and_gitlab_messages_are_printable_and_keep_the_file(hostile):
    sarif = json.loads(report(hostile, "sarif"))
    results = sarif["runs"][0]["results"]
    assert len(results) == 5
    for result in results:
        assert not RAW_CONTROL.search(result["message"]["text"])
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in results}
    # a URI reference, percent-encoded (RFC 3986), which decodes to the file's real name
    assert "src/names_description/launch/title%1B%5D0;pwned%07.launch.py" in uris
    assert (
        "src/names_description/launch/x%0A%3A%3Aerror%20file=README.md,line=1%3A%3Aforged.launch.py" in uris
    )
    assert all(not RAW_CONTROL.search(uri) and " " not in uri for uri in uris)
    assert {unquote(uri, errors="surrogateescape") for uri in uris} == {
        f"src/names_description/launch/{name}"
        for name in (TITLE, CLEAR, FORGED, CONTROL, os.fsdecode(NOT_UTF8))
    }
    gitlab = json.loads(report(hostile, "gitlab"))
    assert all(not RAW_CONTROL.search(issue["description"]) for issue in gitlab)
    # GitLab matches the path to the merge request's files: the real name (JSON escapes it)
    assert {issue["location"]["path"] for issue in gitlab} == {
        f"src/names_description/launch/{name}"
        for name in (TITLE, CLEAR, FORGED, CONTROL, os.fsdecode(NOT_UTF8))
    }


def test_json_report_keeps_the_real_names(hostile):
    text = report(hostile, "json")
    assert not RAW_CONTROL.search(text)  # JSON writes them as \u001b, \n
    paths = {d["path"] for d in json.loads(text)["diagnostics"]}
    assert f"src/names_description/launch/{TITLE}" in paths
    assert f"src/names_description/launch/{FORGED}" in paths
    # a name that is not UTF-8 comes back as its own bytes
    assert os.fsencode("src/names_description/launch/") + NOT_UTF8 in {os.fsencode(p) for p in paths}


def test_explain_launch_and_one_line_errors_escape_names(hostile):
    launch = hostile / "src" / "names_description" / "launch"
    result = run_pkgforge("verify", "--explain-launch", launch / TITLE, cwd=hostile)
    assert result.returncode == 0, result.stderr
    assert not RAW_CONTROL.search(result.stdout)
    assert result.stdout.splitlines()[0] == str(launch / "title\\x1b]0;pwned\\x07.launch.py")
    # a folder that does not exist: the one-line error names it, escaped, on one line
    result = run_pkgforge("verify", "gone\x1b[2J\n::error::forged", cwd=hostile)
    assert result.returncode == 2
    assert result.stderr == f"pkgforge: error: {hostile}/gone\\x1b[2J\\n::error::forged does not exist\n"
