#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Runs every fenced code block of README.md, examples/README.md and docs/*.md as a user pastes it.

Rules (docs/design.md, "Code blocks in the docs"):
- Every fence names its language. sh/bash blocks run with `bash -e`; console blocks run their `$ `
  lines (and the `\\`-continued lines after them) with `bash -e`, the other lines being the output
  shown, not compared; python blocks run with the build's interpreter and PYTHONPATH at the build's
  module. text, json, cmake, cpp, obj and ply blocks are not run.
- A runnable block that must not run in the suite has `<!-- not run by tests: REASON -->` on the line
  before its fence; the report lists it with its reason.
- Each markdown file's blocks run in order in a fresh copy of the source tree (so paths such as
  examples/… resolve as from the repository root and nothing is written into the repository), with
  `build` the build tree, the CLI (`cifs`) on PATH and `python3` the build's interpreter. Beside the
  repository's files they may leave only what their commands name (and out/): a side effect there fails.
- Without the Python module, python blocks and shell blocks naming build/python are skipped.
"""
import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

SHELL = {"sh", "bash", "console"}
RUN = SHELL | {"python"}
NOT_RUN = {"text", "json", "cmake", "cpp", "obj", "ply"}
MARKER = re.compile(r"^\s*<!--\s*not run by tests:(.*?)-->\s*$")
FENCE = re.compile(r"^(\s*)(```+|~~~+)\s*([^\s`]*)")


@dataclass
class Block:
    path: str  # relative to the source tree
    line: int  # line of the opening fence (1-based)
    language: str
    lines: list  # the content lines, indentation of the fence removed
    skip_reason: str = None  # from the marker


@dataclass
class Report:
    failures: list = field(default_factory=list)
    ran: int = 0
    marked: list = field(default_factory=list)
    by_language: dict = field(default_factory=dict)
    without_python: list = field(default_factory=list)


def parse(source: Path, rel: str, report: Report) -> list:
    """The blocks of one markdown file; malformed fences and markers become failures."""
    text = (source / rel).read_text(encoding="utf-8").split("\n")
    blocks, i, pending = [], 0, None  # pending: (line, reason) of a marker awaiting its fence
    while i < len(text):
        marker, fence = MARKER.match(text[i]), FENCE.match(text[i])
        if pending and not fence:
            report.failures.append((f"{rel}:{pending[0]}", "the not-run marker is not on the line before a fence"))
            pending = None
        if marker:
            reason = marker.group(1).strip()
            if not reason:
                report.failures.append((f"{rel}:{i + 1}", "the not-run marker gives no reason"))
            pending = (i + 1, reason)
            i += 1
            continue
        if not fence:
            i += 1
            continue
        indent, ticks, language = fence.group(1), fence.group(2), fence.group(3).lower()
        start, body = i + 1, []
        i += 1
        while i < len(text):
            close = re.match(r"^\s*(" + ticks[0] + "{" + str(len(ticks)) + r",})\s*$", text[i])
            if close:
                break
            body.append(text[i][len(indent):] if text[i].startswith(indent) else text[i].lstrip())
            i += 1
        else:
            report.failures.append((f"{rel}:{start}", "the fence is never closed"))
        i += 1
        block = Block(rel, start, language, body, pending[1] if pending else None)
        pending = None
        if not language:
            report.failures.append((f"{rel}:{start}", "the fence names no language (```text for output, "
                                    "```sh, ```console, ```python for what runs)"))
        elif language not in RUN | NOT_RUN:
            report.failures.append((f"{rel}:{start}", f"unknown fence language '{language}' (runs: "
                                    f"{', '.join(sorted(RUN))}; not run: {', '.join(sorted(NOT_RUN))})"))
        elif language in NOT_RUN and block.skip_reason is not None:
            report.failures.append((f"{rel}:{start}", f"a not-run marker on a {language} block, which never runs"))
        elif language in {"sh", "bash"} and any(line.startswith("$ ") for line in body):
            report.failures.append((f"{rel}:{start}", "a `$ ` prompt in an sh block: fence it as console"))
        elif language == "console" and not any(line.startswith("$ ") for line in body):
            report.failures.append((f"{rel}:{start}", "a console block without a `$ ` command line"))
        else:
            blocks.append(block)
    if pending:
        report.failures.append((f"{rel}:{pending[0]}", "the not-run marker is not on the line before a fence"))
    return blocks


def script(block: Block) -> str:
    """The code to run, padded with empty lines so that line numbers in errors are the markdown's."""
    lines = block.lines
    if block.language == "console":
        lines, continued = [], False
        for line in block.lines:
            command = continued or line.startswith("$ ")
            lines.append((line if continued else line[2:]) if command else "")
            continued = command and line.endswith("\\")
    return "\n" * block.line + "\n".join(lines) + "\n"


def copy_source(source: Path, build: Path, target: Path):
    """The source tree without its git data, build trees and outputs; `build` links to the build tree."""
    def ignore(folder, names):
        skipped = {".git", "__pycache__"}
        if Path(folder).resolve() == source:
            skipped |= {"out"} | {n for n in names if (source / n / "CMakeCache.txt").exists()}
        return [n for n in names if n in skipped or (Path(folder) / n).resolve() == build]
    shutil.copytree(source, target, symlinks=True, ignore=ignore)
    (target / "build").symlink_to(build, target_is_directory=True)


def run_blocks(runnable, rel, cwd, work, shim, env, args, report):
    """Runs one markdown file's blocks in its copy of the source tree, in order."""
    for b in runnable:
        if b.language == "python":
            code = work / "blocks" / f"{rel.replace('/', '_')}_{b.line}.py"
            code.parent.mkdir(exist_ok=True)
            code.write_text(script(b), encoding="utf-8")
            # Compiled under the markdown's name: tracebacks say docs/python.md, line N.
            driver = ("import sys; path, name = sys.argv[1:]; sys.argv = [name]; "
                      "exec(compile(open(path, encoding='utf-8').read(), name, 'exec'), {'__name__': '__main__'})")
            command = [str(shim), "-c", driver, str(code), rel]
            block_env = dict(env, PYTHONPATH=str(args.python_module.resolve()))
        else:
            command = ["bash", "-e", "-c", script(b), rel]
            block_env = env
        t0 = time.monotonic()
        # A session of its own: a timeout ends the block's whole process group, not just bash.
        process = subprocess.Popen(command, cwd=cwd, env=block_env, stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True, errors="replace", start_new_session=True)
        try:
            out, err = process.communicate(timeout=args.timeout)
            status = process.returncode
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            out, err = process.communicate()
            status = f"none: killed after {args.timeout:g} s"
        seconds = time.monotonic() - t0
        report.ran += 1
        where = f"{rel}:{b.line}"
        if status == 0:
            print(f"ok      {where} ({b.language}, {seconds:.1f} s)")
            continue
        print(f"FAILED  {where} ({b.language}, exit {status}, {seconds:.1f} s)")
        detail = f"{b.language} block, exit status {status}, run in {cwd}"
        if err.strip():
            detail += "\n stderr:\n" + tail(err, 60)
        if out.strip():
            detail += "\n stdout:\n" + tail(out, 15)
        report.failures.append((where, detail))


def tail(text: str, count: int) -> str:
    lines = text.rstrip("\n").split("\n")
    kept = lines[-count:]
    return ("  … (" + str(len(lines) - count) + " lines before)\n" if len(lines) > count else "") + \
        "\n".join("  | " + line for line in kept)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--source", type=Path, required=True, help="source tree")
    parser.add_argument("--build", type=Path, required=True, help="build tree (linked as build/)")
    parser.add_argument("--cli", type=Path, required=True, help="the cifs executable")
    parser.add_argument("--work", type=Path, required=True, help="scratch folder (emptied first)")
    parser.add_argument("--python", default=sys.executable, help="interpreter for python blocks and python3")
    parser.add_argument("--python-module", type=Path, help="folder holding the built cifs package")
    parser.add_argument("--python-env", action="append", default=[],
                        help="NAME=VALUE for the interpreter only (e.g. a sanitizer runtime); repeatable")
    parser.add_argument("--timeout", type=float, default=300, help="seconds per block")
    parser.add_argument("--list", action="store_true", help="list the blocks and what would happen, run none")
    parser.add_argument("files", nargs="*", help="markdown files relative to --source (default: all)")
    args = parser.parse_args()
    source, build, work = args.source.resolve(), args.build.resolve(), args.work.resolve()
    files = args.files or ["README.md", "examples/README.md"] + sorted(
        str(p.relative_to(source)) for p in (source / "docs").glob("*.md"))

    shutil.rmtree(work, ignore_errors=True)
    (work / "bin").mkdir(parents=True)
    # python3 on PATH is the interpreter the module was built for (Debian's, with numpy).
    shim = work / "bin" / "python3"
    shim.write_text("#!/bin/sh\nexec env " + " ".join(f"'{e}'" for e in args.python_env) +
                    f" '{args.python}' \"$@\"\n")
    shim.chmod(0o755)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(PATH=f"{work / 'bin'}:{args.cli.resolve().parent}:{env.get('PATH', '/usr/bin:/bin')}",
               MPLBACKEND="Agg", PYTHONDONTWRITEBYTECODE="1")

    report = Report()
    started = time.monotonic()
    for rel in files:
        blocks = parse(source, rel, report)
        runnable = []
        for b in blocks:
            if b.language in NOT_RUN:
                report.by_language[b.language] = report.by_language.get(b.language, 0) + 1
            elif b.skip_reason is not None:
                report.marked.append(b)
            elif not args.python_module and (b.language == "python" or any(
                    name in "\n".join(b.lines) for name in ("build/python", "build/cifs-python"))):
                report.without_python.append(b)
            else:
                runnable.append(b)
        if args.list:
            for b in runnable:
                print(f"would run {b.path}:{b.line} ({b.language})")
        if not runnable or args.list:
            continue
        cwd = work / "files" / rel.replace("/", "_")
        copy_source(source, build, cwd)
        try:
            run_blocks(runnable, rel, cwd, work, shim, env, args, report)
        finally:  # the copy is in the build tree: its `build` link would make any recursive walk of it loop
            (cwd / "build").unlink()
        # What a user pastes writes the files it names, and nothing else beside the repository's files: README's
        # `render clover_fractal.json -o clover.exr --png clover.png` also left clover_fractal.svg there (issue 32).
        named = "\n".join("\n".join(b.lines) for b in runnable)
        left = sorted(n for n in set(os.listdir(cwd)) - set(os.listdir(source)) - {"out"} if n not in named)
        if left:
            report.failures.append((rel, f"its blocks left {', '.join(left)} in the folder they ran in, a file "
                                         "no command names; write such outputs under out/ or name them"))
        sys.stdout.flush()

    for b in report.marked:
        print(f"skipped {b.path}:{b.line} ({b.language}): not run by tests: {b.skip_reason}")
    for b in report.without_python:
        print(f"skipped {b.path}:{b.line} ({b.language}): the build has no Python module")
    languages = ", ".join(f"{n} {k}" for k, n in sorted(report.by_language.items()))
    print(f"\n{report.ran} blocks run in {time.monotonic() - started:.0f} s, {len(report.failures)} failed; "
          f"skipped: {len(report.marked)} marked not to run, {len(report.without_python)} needing the Python "
          f"module (not built), {sum(report.by_language.values())} by language ({languages or 'none'})")
    for where, detail in report.failures:
        print(f"\n{where}: {detail}")
    return 1 if report.failures else 0


if __name__ == "__main__":
    sys.exit(main())
