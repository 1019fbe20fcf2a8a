"""The on-disk cache: keyed on the builder's code as well as its inputs, and never stuck on a damaged entry."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from shroud.base.cache import cached


@pytest.fixture
def builder_module(tmp_path, monkeypatch):
    """A module ``probe_builder`` on the path whose source a test can edit."""
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path / "cache"))
    source = tmp_path / "src" / "probe_builder.py"
    source.parent.mkdir()
    source.write_text("SCALE = 2\n")
    monkeypatch.syspath_prepend(str(source.parent))
    yield source
    sys.modules.pop("probe_builder", None)


def test_editing_the_builders_source_builds_anew(builder_module):
    """Same inputs, edited builder: the old entry (built by the old code) is not reused."""
    builds = []

    def build(path: Path) -> None:
        builds.append(builder_module.read_text())
        path.write_text(builder_module.read_text())

    first = cached("probe", {"n": 1}, ".txt", build, sources=("probe_builder",))
    assert cached("probe", {"n": 1}, ".txt", build, sources=("probe_builder",)) == first
    builder_module.write_text("SCALE = 3\n")
    second = cached("probe", {"n": 1}, ".txt", build, sources=("probe_builder",))
    assert second != first and second.read_text() == "SCALE = 3\n"
    assert builds == ["SCALE = 2\n", "SCALE = 3\n"]


def test_a_truncated_entry_is_rebuilt_with_a_warning(builder_module, capsys):
    def build(path: Path) -> None:
        path.write_text("complete\n")

    def check(path: Path) -> None:
        if not path.read_text().endswith("complete\n"):
            raise ValueError("cut short")

    path = cached("probe", {"n": 2}, ".txt", build, check=check)
    path.write_text("compl")                          # a run killed while writing, a full disk
    capsys.readouterr()
    again = cached("probe", {"n": 2}, ".txt", build, check=check)
    assert again == path and path.read_text() == "complete\n"
    assert "cannot be read (ValueError: cut short)" in capsys.readouterr().err


def test_an_empty_entry_is_rebuilt_without_a_check(builder_module):
    path = cached("probe", {"n": 3}, ".txt", lambda p: p.write_text("x"))
    path.write_bytes(b"")
    assert cached("probe", {"n": 3}, ".txt", lambda p: p.write_text("x")).read_text() == "x"


def test_a_failed_build_leaves_no_entry_and_no_temporary_file(builder_module, tmp_path):
    def build(path: Path) -> None:
        path.write_text("half")
        raise OSError("No space left on device")

    with pytest.raises(OSError):
        cached("probe", {"n": 4}, ".txt", build)
    assert not [p for p in (tmp_path / "cache").rglob("*") if p.is_file()]


def test_the_mesh_file_check_knows_a_cut_mesh(tmp_path):
    from meshes.blade import check_msh_complete
    whole = tmp_path / "m.msh"
    whole.write_text("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Elements\n1 1 1 1\n$EndElements\n")
    check_msh_complete(whole)
    whole.write_text(whole.read_text()[:40])
    with pytest.raises(ValueError):
        check_msh_complete(whole)


def test_a_cold_build_is_told_from_a_warm_one(tmp_path, monkeypatch):
    """cache.builds() collects the entries built in a block (a cold build), none when they are read (warm);
    an entry built inside another counts in the outer one only, so build times are never counted twice."""
    from shroud.base.cache import builds
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path / "cache"))

    def inner(path: Path) -> None:
        path.write_text("mesh")

    def outer(path: Path) -> None:
        cached("probe_mesh", {"n": 1}, ".txt", inner)
        path.write_text("basis")

    with builds() as cold:
        cached("probe_basis", {"n": 1}, ".txt", outer)
    with builds() as warm:
        cached("probe_basis", {"n": 1}, ".txt", outer)
    assert [what for what, _ in cold] == ["probe_basis"] and cold[0][1] >= 0
    assert warm == []
