"""tests/pass_record.py: what decides that a slow test file need not run again."""

import subprocess

import pytest

from pass_record import REMEMBERED, PassRecord, tree_digest


@pytest.fixture
def repo(tmp_path):
    subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    (tmp_path / ".gitignore").write_text("build/\n")
    (tmp_path / "a.py").write_text("x = 1\n")
    subprocess.run(["git", "add", "."], cwd=tmp_path, check=True)
    return tmp_path


def test_every_change_of_a_file_of_the_course_changes_the_digest(repo):
    key = tree_digest(repo)
    (repo / "build").mkdir()
    (repo / "build" / "out.html").write_text("made by a build")
    assert tree_digest(repo) == key, "what the build writes (ignored by git) is not an input"
    (repo / "a.py").write_text("x = 2\n")
    assert tree_digest(repo) != key, "a tracked file's content"
    key = tree_digest(repo)
    (repo / "new.ipynb").write_text("{}")
    assert tree_digest(repo) != key, "a new file not yet added"
    key = tree_digest(repo)
    (repo / "new.ipynb").rename(repo / "renamed.ipynb")
    assert tree_digest(repo) != key, "a file's name"


def test_outside_a_git_checkout_nothing_is_remembered(tmp_path):
    assert tree_digest(tmp_path / "not-a-repo") is None


def test_a_record_is_fresh_only_for_its_own_key(tmp_path, monkeypatch):
    monkeypatch.setattr("pass_record.CACHE", tmp_path)
    monkeypatch.delenv("TEST_FRESH", raising=False)
    PassRecord("files").record({"test_slides.py": "k1"})
    again = PassRecord("files")
    assert again.fresh("test_slides.py", "k1") and not again.fresh("test_slides.py", "k2")
    monkeypatch.setenv("TEST_FRESH", "1")
    assert not PassRecord("files").fresh("test_slides.py", "k1")


def test_the_remembered_files_exist():
    from pathlib import Path
    here = Path(__file__).parent
    assert all((here / name).is_file() for name in REMEMBERED)
