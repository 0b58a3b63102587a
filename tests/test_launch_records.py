"""The record format both launch engines share (src/pkgforge/launch/records.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pkgforge.launch.records import (
    Error,
    LaunchFile,
    Node,
    PackageLookup,
    Recorder,
    RecordKeyError,
    resolution_from_reply,
)


def test_a_renamed_key_fails_loudly_in_the_worker():
    recorder = Recorder()
    recorder.add("packages", {"name": "rviz2", "via": "Node package"})
    with pytest.raises(RecordKeyError, match="PackageLookup has no field pacakge"):
        recorder.add("packages", {"pacakge": "rviz2"})
    with pytest.raises(RecordKeyError, match="Argument has no field defualt"):
        recorder.arguments.setdefault("gui", {"name": "gui", "defualt": "true"})


def test_the_parent_rebuilds_typed_records_merged_across_branches():
    recorder = Recorder()
    for gui in ("true", "false"):
        recorder.branch = {"gui": gui}
        recorder.add(
            "nodes",
            {
                "kind": "node",
                "package": "rviz2",
                "file": "/x.launch.py",
                "line": 3,
                "parameters": [{"name": "a", "form": "typed-str", "value_preview": "1"}],
            },
        )
    recorder.add("packages", {"name": "jsp", "via": "Node package", "found": False})
    reply = {"status": "ok", "error": None, **recorder.dump(), "engine": "ros", "distro": "jazzy"}
    resolution = resolution_from_reply(LaunchFile("p", Path("/x.launch.py"), None), reply)
    (node,) = resolution.nodes
    assert isinstance(node, Node) and node.package == "rviz2" and node.parameters[0].form == "typed-str"
    assert node.branches == ["gui:=true", "gui:=false"]
    assert resolution.packages == [
        PackageLookup(
            name="jsp", via="Node package", found=False, branch={"gui": "false"}, branches=["gui:=false"]
        )
    ]
    assert (resolution.engine, resolution.distro, resolution.branches) == ("ros", "jazzy", 2)


def test_a_worker_reply_with_an_unknown_status_or_key_is_refused():
    launch = LaunchFile("p", Path("/x.launch.py"), None)
    with pytest.raises(ValueError, match="unknown launch status 'finished'"):
        resolution_from_reply(launch, {"status": "finished"})
    with pytest.raises(RecordKeyError):
        resolution_from_reply(launch, {"status": "ok", "errors": [{"stage": "visit", "kind": "x"}]})
    resolution = resolution_from_reply(
        launch, {"status": "timeout", "error": {"message": "slow", "line": None}}
    )
    assert resolution.error == Error(message="slow")


def test_each_record_s_json_shape_names_exactly_its_fields():
    """The TypedDicts the worker's reply is typed with (records.py) and the records the parent
    rebuilds from it have the same keys: a field renamed in one and not the other fails here."""
    import dataclasses
    import typing

    from pkgforge.launch import records

    for cls in [records.Argument, records.Parameter, *records.KINDS.values()]:
        shape = getattr(records, f"{cls.__name__}RecordDict")
        keys = shape.__required_keys__ | shape.__optional_keys__
        assert keys == {f.name for f in dataclasses.fields(cls)}, cls.__name__
    assert set(records.RecordsDict.__optional_keys__) == {"arguments", *records.ITEM_KINDS}
    assert set(records.BranchingDict.__required_keys__) == {
        f.name for f in dataclasses.fields(records.Branching)
    }
    assert records.STATUSES == typing.get_args(records.Status) == ("ok", "load-error", "timeout", "crashed")
