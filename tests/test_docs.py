"""The docs are a handbook: README.md and docs/ say what is true now, and history lives in
git. No text of the repository refers to a past work item by number, and every repository
file that README.md and docs/*.md cite exists."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# Built from parts so that this file does not match its own pattern.
_STOP = "st" + "op"
_ISSUE = "is" + "sue"
HISTORY = re.compile(
    rf"(?<![a-z]){_STOP}s? [0-9]+|(?<![a-z]){_ISSUE}[ _-]?#?[0-9]+", re.IGNORECASE
)

# Files outside the repository that the docs may name: the paper's notes lie beside the
# reference (shared/reference/NOTES.md), not in the repository.
# ``results.md`` is a file `pdamper paper` writes.
OUTSIDE = {"NOTES.md", "results.md"}

_TOKEN = re.compile(r"`([^`\n]+)`|\]\(([^)\s]+)\)")
_PATH = re.compile(r"(?:[\w.-]+/)*[\w.-]+\.(?:py|md)|(?:src|tests|docs|benchmarks|\.ci)/[\w./-]+")


def _texts():
    yield ROOT / "README.md"
    yield from sorted((ROOT / "docs").glob("*.md"))
    for top in ("src", "tests", "benchmarks"):
        yield from sorted((ROOT / top).rglob("*.py"))


def _docs():
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def test_no_text_refers_to_a_past_work_item_by_number():
    hits = []
    for path in _texts():
        for no, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if HISTORY.search(line):
                hits.append(f"{path.relative_to(ROOT)}:{no}: {line.strip()}")
    assert not hits, "history belongs in git:\n" + "\n".join(hits)


def test_the_pattern_finds_what_it_is_meant_to():
    for text in (f"{_STOP} 21's kernels", f"{_STOP}s 21-23", f"({_ISSUE} 9)",
                 f"the {_ISSUE}-11 corpus", f"{_ISSUE}11_corpus", f"keys_of_{_ISSUE}_9",
                 f"{_ISSUE} #9's map",
                 f"{_STOP.capitalize()} 19's rule"):
        assert HISTORY.search(text), text
    for text in ("the run stops at the first whole cycle", "a quiet stop: 4.7 %",
                 "tissue 3"):
        assert not HISTORY.search(text), text


def _cited_paths(text):
    """Repository paths cited in backticks or link targets, without ``::test`` suffixes,
    anchors or line numbers."""
    for match in _TOKEN.finditer(text):
        token = match.group(1) or match.group(2)
        for word in re.split(r"[\s,;()]+", token):
            word = word.split("::")[0].split("#")[0]
            word = re.sub(r":\d+$", "", word).rstrip(".")
            if "://" in word or word.startswith(("-", "$", "~", "/")) or "*" in word \
                    or "<" in word or "{" in word:
                continue
            if _PATH.fullmatch(word):
                yield word


def _exists(doc, cited):
    if Path(cited).name in OUTSIDE:
        return True
    if (ROOT / cited).exists() or (doc.parent / cited).exists():
        return True
    # A bare file name (``bench_map.py``) names a repository file somewhere in the tree.
    return "/" not in cited and any(_repo_files(cited))


def _repo_files(name):
    for top in ("src", "tests", "docs", "benchmarks", ".ci"):
        yield from (ROOT / top).rglob(name)


def test_every_repository_file_the_docs_cite_exists():
    missing = []
    for doc in _docs():
        for cited in sorted(set(_cited_paths(doc.read_text(encoding="utf-8")))):
            if not _exists(doc, cited):
                missing.append(f"{doc.relative_to(ROOT)}: {cited}")
    assert not missing, "cited but not in the repository:\n" + "\n".join(missing)


def test_the_path_check_sees_a_missing_file():
    text = "see `tests/cli/test_corpus.py::test_x` and [fields](docs/no_such_file.md)"
    cited = list(_cited_paths(text))
    assert cited == ["tests/cli/test_corpus.py", "docs/no_such_file.md"]
    assert _exists(ROOT / "README.md", cited[0])
    assert not _exists(ROOT / "README.md", cited[1])
