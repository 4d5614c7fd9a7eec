"""The repository is self-contained: nothing in it cites a document that lives outside it,
and every relative link of its Markdown files leads to a file in it.

A user who clones the project has the repository and nothing else: the design is
``docs/design.md`` and the references are named by title and authors (docs/design.md,
"The references"). The files checked are those git knows (tracked, or new and not
ignored) and that exist in the work tree; ``benchmarks/results/`` holds measurement
records, which are left as they were written.
"""

from __future__ import annotations

import re
import subprocess
import urllib.parse
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

#: Text files checked for citations of documents outside the repository.
TEXT_SUFFIXES = (".py", ".md", ".toml", ".txt", ".cfg")
#: Folders left out (recorded results).
EXCLUDED = ("benchmarks/results/",)

# The patterns are assembled from pieces so that this file does not cite them itself.
_DESIGN = "DESIGN" + ".md"
#: (what it is, pattern) of every citation of a document outside the repository.
OUTSIDE_CITATIONS = (
    ("a folder beside the checkout", re.compile(re.escape(".." + "/shared"))),
    ("the folder of the reference papers outside the repository",
     re.compile(re.escape("shared" + "/reference"))),
    (f"the design notes outside the repository ({_DESIGN}; the design is docs/design.md)",
     re.compile(re.escape(_DESIGN))),
    ("a reference paper's file outside the repository (name the paper by title and authors)",
     re.compile("|".join(re.escape(stem + "-") + r"\S*" for stem in (
         "westin2018" + "-cable-sheave", "nodal-position" + "-fem-towed-cable", "gomes2021" + "-towing-cable")))),
)

#: Inline links and images ``[text](target)``, ``![alt](target "title")``.
_INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+[\"'(][^)]*)?\)")
#: Reference definitions ``[label]: target``.
_REFERENCE_LINK = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+.*)?$", re.MULTILINE)
_FENCE = re.compile(r"^\s*(```|~~~)")
_CODE_SPAN = re.compile(r"(`+)(.+?)\1")
_SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


def repository_files() -> list[str]:
    """Paths (relative, POSIX) of the files git tracks or would add, that exist."""
    try:
        run = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
                             cwd=ROOT, capture_output=True, check=True)
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout: the repository's file list is unknown")
    names = sorted({n for n in run.stdout.decode().split("\0") if n})
    return [n for n in names if (ROOT / n).is_file()]


def _checked(name: str) -> bool:
    return name.endswith(TEXT_SUFFIXES) and not name.startswith(EXCLUDED)


def outside_citations(text: str) -> list[tuple[int, str, str]]:
    """(line number, what, line) of every citation of a document outside the repository."""
    found = []
    for number, line in enumerate(text.splitlines(), start=1):
        for what, pattern in OUTSIDE_CITATIONS:
            if pattern.search(line):
                found.append((number, what, line.strip()))
    return found


def _prose(text: str) -> str:
    """The Markdown text without fenced code blocks and code spans (same line numbers)."""
    lines, fenced = [], False
    for line in text.splitlines():
        if _FENCE.match(line):
            fenced = not fenced
            lines.append("")
        else:
            lines.append("" if fenced else _CODE_SPAN.sub(lambda m: " " * len(m.group(0)), line))
    return "\n".join(lines)


def link_targets(text: str) -> list[str]:
    """Every link target of a Markdown text (code left out)."""
    prose = _prose(text)
    return [m.group(1) for m in _INLINE_LINK.finditer(prose)] + [m.group(1) for m in _REFERENCE_LINK.finditer(prose)]


def anchors(text: str) -> set[str]:
    """The anchors GitHub gives the headings of a Markdown text."""
    seen: dict[str, int] = {}
    out = set()
    for line in _prose(text.replace("`", "")).splitlines():
        m = re.match(r"^\s{0,3}#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not m:
            continue
        slug = re.sub(r"[^\w\- ]", "", m.group(1).lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        out.add(slug if n == 0 else f"{slug}-{n}")
    return out


def broken_links(source: str, files: list[str], root: Path = ROOT) -> list[str]:
    """Relative links of the Markdown file ``source`` whose file (or heading) is not in the
    repository at ``root`` (whose files are ``files``), each with the reason."""
    present = set(files)
    folders = {p.as_posix() for f in files for p in Path(f).parents}
    text = (root / source).read_text(encoding="utf-8")
    broken = []
    for target in link_targets(text):
        if _SCHEME.match(target) or target.startswith("//"):
            continue  # a web address
        path, _, anchor = urllib.parse.unquote(target).partition("#")
        if path.startswith("/"):
            broken.append(f"{target}: an absolute path")
            continue
        resolved = (root / source).parent / path if path else root / source
        try:
            relative = resolved.resolve().relative_to(root.resolve()).as_posix()
        except ValueError:
            broken.append(f"{target}: outside the repository")
            continue
        if relative not in present and relative.rstrip("/") not in folders:
            broken.append(f"{target}: no such file in the repository")
        elif (anchor and relative.endswith(".md") and relative in present
              and anchor not in anchors((root / relative).read_text(encoding="utf-8"))):
            broken.append(f"{target}: no heading '#{anchor}' in {relative}")
    return broken


def test_nothing_cites_a_document_outside_the_repository():
    problems = []
    for name in filter(_checked, repository_files()):
        text = (ROOT / name).read_text(encoding="utf-8", errors="replace")
        problems += [f"{name}:{number}: {what}: {line}" for number, what, line in outside_citations(text)]
    assert not problems, "citations of documents outside the repository:\n" + "\n".join(problems)


def test_the_design_document_is_in_the_repository_and_the_readme_links_it():
    files = repository_files()
    assert "docs/design.md" in files
    assert "docs/design.md" in link_targets((ROOT / "README.md").read_text(encoding="utf-8"))


def test_every_relative_markdown_link_leads_to_a_file_of_the_repository():
    files = repository_files()
    sources = [f for f in files if f.endswith(".md") and (f == "README.md" or f.startswith("docs/"))]
    assert "README.md" in sources
    problems = [f"{source}: {b}" for source in sources for b in broken_links(source, files)]
    assert not problems, "broken links:\n" + "\n".join(problems)


@pytest.mark.parametrize("line", [
    "see ../" + "shared/notes.md",
    "the thesis (shared" + "/reference/westin.md)",
    "as in " + "DESIGN" + ".md",
    "eq. 3 of " + "nodal-position" + "-fem-towed-cable-paper.md",
])
def test_outside_citations_are_found(line):
    assert outside_citations(line)


def test_a_link_to_a_missing_file_or_heading_is_broken(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "a.md").write_text("# Title\n\n## Some section, with `code`\n")
    (tmp_path / "README.md").write_text(
        "[ok](docs/a.md) [ok](docs/a.md#some-section-with-code) [ok](docs/) [ok](#title-here)\n"
        "[web](https://example.org/x.md) `[code](missing.md)`\n\n```\n[code](missing.md)\n```\n"
        "# Title here\n"
        "[gone](docs/missing.md) [anchor](docs/a.md#nowhere) [out](../elsewhere.md)\n")
    broken = broken_links("README.md", ["README.md", "docs/a.md"], root=tmp_path)
    assert [b.split(":")[0] for b in broken] == ["docs/missing.md", "docs/a.md#nowhere", "../elsewhere.md"]


#: A path of a project file quoted in the docs (``towcable_fmu/cosim/loop.py``).
_PROJECT_PATH = re.compile(r"\b(?:towcable_fmu|ship_motion|controllers|tests|benchmarks|docs)/[A-Za-z0-9_./-]*"
                           r"[A-Za-z0-9_]\.(?:py|toml|md|json|csv)\b")


def quoted_paths(text: str) -> set[str]:
    """Project file paths a Markdown text names (in prose or code spans)."""
    return set(_PROJECT_PATH.findall(text))


def test_every_project_file_the_docs_name_exists():
    """A module moved or renamed must take its mentions in the README and docs/ along."""
    sources = ["README.md", *sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md")),
               "ship_motion/README.md", "controllers/README.md"]
    missing = sorted((source, path) for source in sources if (ROOT / source).exists()
                     for path in quoted_paths((ROOT / source).read_text(encoding="utf-8"))
                     if not (ROOT / path).exists() and "<" not in path)
    assert missing == []


def test_quoted_paths_are_found():
    text = "The loop (`towcable_fmu/cosim/loop.py`) and tests/test_layers.py; not towcable_fmu/ alone."
    assert quoted_paths(text) == {"towcable_fmu/cosim/loop.py", "tests/test_layers.py"}
