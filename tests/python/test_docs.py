"""The documents: every repository path they cite exists, and the README's worked example runs
as written (its `damfem check` and its quick `damfem safety` of the worked dam)."""

import json
import re
import shlex
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOCUMENTS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]

# a path inside the repository: a top-level directory of it, then names of files and folders
CITED = re.compile(r"(?<![\w./-])((?:src|tests|geo|scripts|docs|examples)/[\w./-]*[\w/])")
# the target of a Markdown link or image to a file, relative to the document
LINK = re.compile(r"\]\(([\w./-]+\.(?:md|png|svg|rs|py|toml|geo|msh|txt|csv))(?:#[\w-]*)?\)")
# a link to a heading of a Markdown document: its target and the anchor
ANCHOR = re.compile(r"\]\(([\w./-]*)#([^)\s]+)\)")


def anchors(document):
    """The anchors of a Markdown document's headings, as GitHub makes them."""
    found = set()
    for line in document.read_text().splitlines():
        if re.match(r"#{1,6} ", line):
            title = line.lstrip("#").strip().lower()
            found.add(re.sub(r"[^\w\- ]", "", title).replace(" ", "-"))
    return found


def cited_paths(document):
    """(path, line number) of every repository path the document cites, and of every local
    link target, resolved against the repository or the document's folder."""
    cited = []
    for number, line in enumerate(document.read_text().splitlines(), 1):
        for match in CITED.finditer(line):
            path = match.group(1).rstrip(".")
            if line.startswith(".*", match.end()):
                # `geo/dam_on_rock.*`: the files of that stem
                found = next(iter((REPO / path).parent.glob((REPO / path).name + ".*")), REPO / path)
                cited.append((found, path + ".*", number))
            else:
                cited.append((REPO / path, path, number))
        for target in LINK.findall(line):
            cited.append((document.parent / target, target, number))
    return cited


def test_the_scanner_finds_the_citations():
    # the README cites the worked scene and links the reference
    found = {shown for _, shown, _ in cited_paths(REPO / "README.md")}
    assert "geo/dam_combinations.toml" in found
    assert "docs/reference.md" in found
    assert any(shown.startswith("src/") for document in DOCUMENTS for _, shown, _ in cited_paths(document))


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda d: str(d.relative_to(REPO)))
def test_every_path_a_document_cites_exists(document):
    missing = [f"{document.name}:{number}: {shown}" for path, shown, number in cited_paths(document)
               if not path.exists()]
    assert not missing, "paths cited that do not exist:\n" + "\n".join(missing)


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda d: str(d.relative_to(REPO)))
def test_every_heading_a_document_links_exists(document):
    missing = []
    for number, line in enumerate(document.read_text().splitlines(), 1):
        for target, anchor in ANCHOR.findall(line):
            linked = document.parent / target if target else document
            if linked.suffix == ".md" and linked.exists() and anchor not in anchors(linked):
                missing.append(f"{document.name}:{number}: {target}#{anchor}")
    assert not missing, "links to headings that do not exist:\n" + "\n".join(missing)


def readme_commands():
    """The `damfem check` and `damfem safety` commands of the README's worked example, as written."""
    text = (REPO / "README.md").read_text()
    return [c for c in re.findall(r"`(damfem (?:check|safety) geo/dam_combinations\.toml[^`]*)`", text)]


def test_the_readme_worked_example_runs_as_written(damfem, tmp_path):
    commands = readme_commands()
    check = [c for c in commands if c.startswith("damfem check")]
    quick = [c for c in commands if c.startswith("damfem safety") and "--max-steps 1" in c]
    assert check and quick, f"the README's worked example has no check or quick safety command: {commands}"
    for command in check + quick:
        args = shlex.split(command)
        # run from the repository as written, with the output directory under tmp_path
        if "-o" in args:
            args[args.index("-o") + 1] = str(tmp_path / args[args.index("-o") + 1])
        done = subprocess.run([str(damfem), *args[1:]], cwd=REPO, capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, f"{command}: exit {done.returncode}\n{done.stderr}"
        if args[1] == "check":
            assert "geo/dam_combinations.toml: ok" in done.stdout
            # the lines the README quotes from the check
            readme = (REPO / "README.md").read_text()
            for line in done.stdout.splitlines():
                if line.startswith("joint    base") or line.startswith("uplift   combination flood"):
                    assert line in readme, f"the README quotes another line than `{line}`"
        else:
            out = Path(args[args.index("-o") + 1])
            report = (out / "report.md").read_text()
            safety = json.loads((out / "safety.json").read_text())
            assert safety["verdict"], "no verdict"
            assert "Code check" in report and "classical" in report
            for name in ["base_stresses.png", "joint.csv", "dam_combinations.pvd"]:
                assert (out / name).is_file(), name
            # the README quotes this run's numbers: FS_LE and the crack of the usual combination
            readme = (REPO / "README.md").read_text()
            for value in [safety["sliding_safety_factor"], safety["crack_length"]]:
                assert f"{value:.4f}" in readme, f"the README does not quote {value:.4f} of {command}"


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda d: str(d.relative_to(REPO)))
def test_every_test_a_document_names_exists(document):
    # `cargo test --release --test <crate> <filter>`: the filter is part of the path of a test
    # of that crate (a module, tests/<crate>/<module>.rs, or a function)
    missing = []
    text = re.sub(r"`\s*\n\s*", "` ", document.read_text().replace("\n", " "))
    for crate, name in re.findall(r"--test (\w+) (\w+)", text):
        folder = REPO / "tests" / crate
        sources = list(folder.rglob("*.rs")) if folder.is_dir() else []
        modules = {p.stem for p in sources}
        functions = {f for p in sources for f in re.findall(r"fn (\w+)", p.read_text())}
        if not sources or not any(name in m for m in modules | functions):
            missing.append(f"--test {crate} {name}")
    assert not missing, "tests named that do not exist:\n" + "\n".join(missing)


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda d: str(d.relative_to(REPO)))
def test_every_example_a_document_names_exists(document):
    # `cargo run --release --example <name>`: examples/<name>.rs
    text = document.read_text()
    missing = sorted({name for name in re.findall(r"--example (\w+)", text)
                      if not (REPO / "examples" / f"{name}.rs").is_file()})
    assert not missing, "examples named that do not exist:\n" + "\n".join(missing)
