"""verify/forked.py: a map over forked children that share this process's memory, whose answers
are always the serial map's (in order, with its exceptions), whatever happens to a child."""

from __future__ import annotations

import os
import tempfile
import threading

import pytest

from pkgforge.verify.forked import FORK_THRESHOLD, forked_map

ITEMS = list(range(FORK_THRESHOLD * 3 + 5))
PARENT = os.getpid()


def square_where(item: int) -> tuple[int, bool]:
    return item * item, os.getpid() == PARENT


def test_answers_in_order_and_children_did_their_slices():
    answers = forked_map(square_where, ITEMS, jobs=3)
    assert [value for value, _ in answers] == [i * i for i in ITEMS]
    here = [i for i, (_, in_parent) in zip(ITEMS, answers, strict=True) if in_parent]
    assert here == ITEMS[: len(here)] and 0 < len(here) < len(ITEMS)  # the first slice only, here


def test_few_items_one_job_or_a_running_thread_map_here():
    assert all(here for _, here in forked_map(square_where, ITEMS[: FORK_THRESHOLD - 1], jobs=2))
    assert all(here for _, here in forked_map(square_where, ITEMS, jobs=1))
    stop = threading.Event()
    thread = threading.Thread(target=stop.wait)
    thread.start()
    try:  # a lock another thread holds would stay held in a child: no fork then
        assert all(here for _, here in forked_map(square_where, ITEMS, jobs=2))
    finally:
        stop.set()
        thread.join()


def die_in_a_child(item: int) -> int:
    if os.getpid() != PARENT and item == len(ITEMS) - 1:
        os._exit(3)  # killed, as the OOM killer would
    return -item


def test_a_child_that_dies_has_its_slice_done_here():
    assert forked_map(die_in_a_child, ITEMS, jobs=2) == [-i for i in ITEMS]


def refuse(item: int) -> int:
    if item == len(ITEMS) - 2:
        raise ValueError(f"no {item}")
    return item


def test_an_exception_of_the_function_is_raised_here_as_the_serial_map_raises_it():
    with pytest.raises(ValueError, match=f"^no {len(ITEMS) - 2}$"):
        forked_map(refuse, ITEMS, jobs=2)


def unpicklable(item: int) -> object:
    return (lambda: item) if os.getpid() != PARENT else item


def test_an_answer_that_cannot_come_back_is_computed_here():
    assert forked_map(unpicklable, ITEMS, jobs=2) == ITEMS


def test_children_leave_this_process_s_temporary_folders_alone():
    """A child ends without this process's exit handlers: the install tree (a temporary folder
    cleaned up at exit) is still there after the map."""
    with tempfile.TemporaryDirectory() as folder:
        marker = os.path.join(folder, "tree")
        open(marker, "w").close()
        forked_map(square_where, ITEMS, jobs=2)
        assert os.path.exists(marker)


def _forks_allowed(monkeypatch, allowed: int) -> list[int]:
    """os.fork succeeds `allowed` times, then the system refuses it (EAGAIN, as at the process
    limit); → the pids it gave."""
    import errno

    real, given = os.fork, []

    def fork() -> int:
        if len(given) >= allowed:
            raise OSError(errno.EAGAIN, "Resource temporarily unavailable")
        pid = real()
        if pid:
            given.append(pid)
        return pid

    monkeypatch.setattr(os, "fork", fork)
    return given


def _gone(pids: list[int]) -> bool:
    return all(not os.path.exists(f"/proc/{pid}") for pid in pids)


@pytest.mark.parametrize("allowed", [0, 1])
def test_a_fork_refused_has_its_slice_done_here_and_leaves_nothing_waiting(monkeypatch, allowed):
    """No child at all, or the second fork refused after the first worked (a pool kept that first
    worker, and the exit handlers waited for it forever): the serial answers, every child reaped."""
    given = _forks_allowed(monkeypatch, allowed)
    answers = forked_map(square_where, ITEMS, jobs=3)
    assert [value for value, _ in answers] == [i * i for i in ITEMS]
    assert len(given) == allowed and _gone(given)
    here = sum(1 for _, in_parent in answers if in_parent)
    assert here == (len(ITEMS) if allowed == 0 else len(ITEMS) - len(ITEMS) // 3 - 1)


@pytest.mark.parametrize("allowed", [0, 1])
def test_model_loading_without_loader_processes_loads_every_model_here(
    tmp_path, template_package, monkeypatch, allowed
):
    """verify's parallel model loading (16 packages or more) when no loader, or only the first,
    can be forked: the same targets and models, the rest loaded in this process, not an error,
    and no loader left behind."""
    import shutil

    from pkgforge.verify.discovery import PARALLEL_THRESHOLD, load_models
    from pkgforge.workspace import Workspace

    for number in range(PARALLEL_THRESHOLD + 1):
        shutil.copytree(template_package, tmp_path / "src" / f"copy{number:02d}" / "rob_description")
    workspace = Workspace(tmp_path, tmp_path / "src")
    targets, models = load_models(workspace, 2)

    given = _forks_allowed(monkeypatch, allowed)
    alone_targets, alone_models = load_models(workspace, 2)
    assert len(given) == allowed and _gone(given)
    assert alone_targets == targets and len(targets) == PARALLEL_THRESHOLD + 1
    assert {p: (m.name, m.build_type, sorted(map(str, m.files))) for p, m in alone_models.items()} == {
        p: (m.name, m.build_type, sorted(map(str, m.files))) for p, m in models.items()
    }
