"""The kernel benchmark's parent checkouts (benchmarks.kernel): the cache keeps only the
most recently used ones."""

import os

from benchmarks.kernel import prune_parents


def test_prune_parents_keeps_the_most_recently_used(tmp_path):
    for age, name in enumerate(["newest", "second", "third", "oldest"]):
        folder = tmp_path / name
        (folder / "src").mkdir(parents=True)
        os.utime(folder, (1e9 - 1000 * age, 1e9 - 1000 * age))
    (tmp_path / "half.part").mkdir()  # a checkout being copied in is never taken for an old one
    removed = prune_parents(tmp_path, keep=2)
    assert sorted(p.name for p in removed) == ["oldest", "third"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["half.part", "newest", "second"]
    assert prune_parents(tmp_path / "missing") == []
