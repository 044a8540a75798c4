"""The front door and docs/ link only to what exists: every relative Markdown link or image in README.md
and docs/*.md names a file or folder of the checkout, and a ``#anchor`` into a Markdown file names one of
its headings (GitHub's anchor rule). Why: the manual moved from README.md into docs/ (issue 62), and a
link left pointing at a moved section, a renamed heading or a figure no stage commits fails silently on
GitHub."""

import re
from pathlib import Path

PAGES = [Path("README.md"), *sorted(Path("docs").glob("*.md"))]
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^)\s]+)\)")  # [text](target), ![alt](target)
FENCE = re.compile(r"^```.*?^```", re.MULTILINE | re.DOTALL)
CODE = re.compile(r"(`+)(?!`).+?(?<!`)\1(?!`)", re.DOTALL)  # an inline code span, ``a `b` c`` too


def links(text: str) -> list[str]:
    """Relative link targets of a Markdown text, code blocks and inline code left out."""
    text = CODE.sub(lambda m: "x" * len(m.group()), FENCE.sub("", text))  # `[x](y)` in code is not a link
    return [t for t in LINK.findall(text) if not re.match(r"[a-z]+:", t)]


def anchors(markdown: Path) -> set[str]:
    """GitHub's anchors for the headings of ``markdown``: link markup and backticks dropped, lower case,
    punctuation but hyphens removed, spaces to hyphens; a repeated heading gets -1, -2, ..."""
    seen: dict[str, int] = {}
    found = set()
    for line in FENCE.sub("", markdown.read_text(encoding="utf8")).splitlines():
        heading = re.match(r"#{1,6} +(.*?)\s*$", line)
        if not heading:
            continue
        text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading.group(1)).replace("`", "")
        slug = re.sub(r"[^\w\- ]", "", text.lower()).replace(" ", "-")
        found.add(slug if slug not in seen else f"{slug}-{seen[slug]}")
        seen[slug] = seen.get(slug, 0) + 1
    return found


def broken(page: Path) -> list[str]:
    out = []
    for target in links(page.read_text(encoding="utf8")):
        path, _, anchor = target.partition("#")
        where = (page.parent / path) if path else page
        if not where.exists():
            out.append(f"{page}: {target} (no such file)")
        elif anchor and where.suffix == ".md" and anchor not in anchors(where):
            out.append(f"{page}: {target} (no heading with that anchor)")
    return out


def test_every_relative_link_in_readme_and_docs_resolves():
    assert len(PAGES) > 1 and all(links(p.read_text(encoding="utf8")) for p in PAGES)  # the parser finds links
    problems = [line for page in PAGES for line in broken(page)]
    assert not problems, "\n".join(problems)


def test_the_checker_sees_a_broken_link_and_anchor(tmp_path):
    (tmp_path / "there.md").write_text("# A heading: with `code`\n")
    page = tmp_path / "page.md"
    page.write_text("[ok](there.md#a-heading-with-code) [gone](missing.md) ![img](nope.png)\n[bad](there.md#nope)\n"
                    "```\n[in code](ignored.md)\n```\n[web](https://example.org) `[inline](ignored.md)`\n"
                    "[`code` text](gone.md)\n")
    assert broken(page) == [f"{page}: missing.md (no such file)", f"{page}: nope.png (no such file)",
                            f"{page}: there.md#nope (no heading with that anchor)",
                            f"{page}: gone.md (no such file)"]
