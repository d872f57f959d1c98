"""The docs are a handbook: README.md and docs/ say what is true now, and history lives in
git. No text of the repository refers to a past work item by number; every repository file,
relative link, test and section that README.md and docs/*.md cite exists (and every test
and section the code's docstrings cite); the README stays short."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# Built from parts so that this file does not match its own pattern.
_STOP = "st" + "op"
_ISSUE = "is" + "sue"
HISTORY = re.compile(
    rf"(?<![a-z]){_STOP}s?[ -][0-9]+|(?<![a-z]){_ISSUE}[ _-]?#?[0-9]+", re.IGNORECASE
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
                 f"{_ISSUE} #9's map", f"the {_STOP}-22 rows",
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


# --- links, anchors, cited tests and sections -------------------------------------------

_LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
_TEST = re.compile(r"([\w./-]+\.py)::(\w+)")
#: ``docs/dem.md, "Integrators"``, ``docs/fields.md, section 1``, ``docs/dem.md, Kernels``
_SECTION = re.compile(r"((?:docs/)?[\w-]+\.md),\s+(?:\"([^\"]+)\"|section (\d+)"
                      r"|([A-Z][A-Za-z-]+)\b)")
#: ``"Speed against LIGGGHTS" below``: a section of the same page
_HERE = re.compile(r"\"([A-Z][^\"]{2,80})\"\s+(?:below|above)")


def _headings(path):
    """The headings of a markdown file, outside code blocks."""
    out, fenced = [], False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and (m := re.match(r"#{1,6}\s+(.*)", line)):
            out.append(m.group(1).strip())
    return out


def _slug(heading):
    """GitHub's anchor of a heading."""
    text = heading.lower().replace("`", "")
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


def _plain(text):
    return " ".join(text.replace("`", "").lower().split())


def _has_section(path, title):
    want = _plain(title)
    return any(_plain(h).startswith(want) for h in _headings(path))


def _md_file(doc, cited):
    for base in (doc.parent, ROOT, ROOT / "docs"):
        if (base / cited).is_file():
            return base / cited
    return None


def _link_problems(doc):
    text = doc.read_text(encoding="utf-8")
    for target in _LINK.findall(text):
        if "://" in target or target.startswith("mailto:"):
            continue
        file, _, anchor = target.partition("#")
        path = (doc.parent / file) if file else doc
        if not path.exists():
            yield f"{doc.relative_to(ROOT)}: link to a missing file: {target}"
        elif anchor and path.suffix == ".md" and \
                anchor not in {_slug(h) for h in _headings(path)}:
            yield f"{doc.relative_to(ROOT)}: link to a missing section: {target}"


def test_every_relative_link_and_anchor_of_the_docs_resolves():
    problems = [p for doc in _docs() for p in _link_problems(doc)]
    assert not problems, "\n".join(problems)


def _test_problems(path):
    for file, name in set(_TEST.findall(path.read_text(encoding="utf-8"))):
        candidates = [ROOT / file] if "/" in file else list(_repo_files(file))
        candidates = [c for c in candidates if c.is_file()]
        if not candidates:
            yield f"{path.relative_to(ROOT)}: {file} (no such file)"
        elif not any(re.search(rf"^\s*(?:async )?(?:def|class) {name}\b",
                               c.read_text(encoding="utf-8"), re.MULTILINE)
                     for c in candidates):
            yield f"{path.relative_to(ROOT)}: {file}::{name} (no such test)"


def test_every_cited_test_exists():
    problems = [p for path in _texts() if path != Path(__file__).resolve()
                for p in _test_problems(path)]
    assert not problems, "cited tests that do not exist:\n" + "\n".join(problems)


def _section_problems(path):
    text = path.read_text(encoding="utf-8")
    for m in _SECTION.finditer(text):
        cited, quoted, number, word = m.groups()
        target = _md_file(path, cited)
        if target is None:
            continue  # a missing file is the file check's to report
        if quoted is not None:
            ok = _has_section(target, quoted)
        elif number is not None:
            ok = any(h.startswith(f"{number}.") for h in _headings(target))
        else:
            ok = _has_section(target, word)
        if not ok:
            yield f"{path.relative_to(ROOT)}: {m.group(0)}"
    if path.suffix == ".md":
        for title in _HERE.findall(text):
            if not _has_section(path, title):
                yield f"{path.relative_to(ROOT)}: \"{title}\" (not a section of this page)"


def test_every_cited_section_exists():
    problems = [p for path in _texts() if path != Path(__file__).resolve()
                for p in _section_problems(path)]
    assert not problems, "cited sections that do not exist:\n" + "\n".join(problems)


def test_the_link_and_section_checks_see_what_is_missing(tmp_path):
    doc = ROOT / "docs" / "dem.md"
    assert _has_section(doc, "Integrators")
    assert not _has_section(doc, "No such section here")
    assert _slug("The report: `pdamper paper --out DIR` writes `DIR/report.html`") == \
        "the-report-pdamper-paper---out-dir-writes-dirreporthtml"
    m = _SECTION.search('see docs/dem.md, "Integrators" and')
    assert m and m.group(2) == "Integrators"
    assert _TEST.findall("`tests/test_docs.py::test_no_such_thing`") == \
        [("tests/test_docs.py", "test_no_such_thing")]


def test_the_readme_is_short():
    lines = (ROOT / "README.md").read_text(encoding="utf-8").count("\n")
    assert lines < 200, f"README.md has {lines} lines; the handbook's pages take the rest"


# --- getting-started.md covers every command and lists every page ------------------------

_GETTING_STARTED = ROOT / "docs" / "getting-started.md"


def _commands():
    """The commands `pdamper --help` lists (the click group typer builds)."""
    import typer.main

    from pdamper.cli import _app

    _app._register()
    return sorted(typer.main.get_command(_app.app).commands)


def _layout_block():
    """The code block of getting-started.md's section "Layout of the code"."""
    text = _GETTING_STARTED.read_text(encoding="utf-8")
    section = text.split("## Layout of the code", 1)[1].split("\n## ", 1)[0]
    return section.split("```", 2)[1]


def _missing_commands(text, commands):
    return [c for c in commands if not re.search(rf"`pdamper {re.escape(c)}(?![\w-])", text)]


def test_getting_started_covers_every_command():
    commands = _commands()
    assert "frf" in commands and len(commands) >= 11
    missing = _missing_commands(_GETTING_STARTED.read_text(encoding="utf-8"), commands)
    assert not missing, "commands of `pdamper --help` missing from getting-started.md: " \
        + ", ".join(missing)


def test_the_command_check_sees_a_missing_command():
    text = "`pdamper cor-sensitivity` and `pdamper map --model dem`"
    assert _missing_commands(text, ["cor", "cor-sensitivity", "map"]) == ["cor"]


def test_getting_started_lists_every_docs_page_and_package():
    block = _layout_block()
    pages = sorted(p.name for p in (ROOT / "docs").glob("*.md"))
    missing = [name for name in pages if not re.search(rf"(?<![\w-]){re.escape(name)}", block)]
    src = ROOT / "src" / "pdamper"
    packages = sorted(p.name for p in src.iterdir()
                      if (p / "__init__.py").is_file() and not p.name.startswith("_"))
    missing += [f"{name}/" for name in packages if f"{name}/" not in block]
    assert not missing, "not in getting-started.md's layout: " + ", ".join(missing)
