#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The code-block runner on small markdown files: what runs, what is skipped, how failures read."""
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

RUNNER = Path(__file__).resolve().with_name("run_code_blocks.py")


class RunCodeBlocks(unittest.TestCase):
    def run_on(self, markdown, *extra):
        """Runs the runner on a source tree holding README.md = markdown; returns (status, output)."""
        with tempfile.TemporaryDirectory() as folder:
            root = Path(folder)
            source, build = root / "src", root / "build"
            (source / "docs").mkdir(parents=True)
            build.mkdir()
            (source / "README.md").write_text(markdown)
            (source / "data.txt").write_text("from the source tree\n")
            result = subprocess.run(
                [sys.executable, str(RUNNER), "--source", str(source), "--build", str(build), "--cli", "/bin/true",
                 "--work", str(root / "work"), "--python", sys.executable, *extra, "README.md"],
                capture_output=True, text=True)
            self.assertEqual(sorted(p.name for p in source.iterdir()), ["README.md", "data.txt", "docs"])
            return result.returncode, result.stdout + result.stderr

    def test_blocks_run_in_a_copy_of_the_source_tree(self):
        status, out = self.run_on("```sh\ncat data.txt > copy.txt\ncmp data.txt copy.txt\ntest -L build\n```\n")
        self.assertEqual(status, 0, out)
        self.assertIn("ok      README.md:1 (sh", out)

    def test_no_link_to_the_build_tree_is_left_behind(self):
        """The copies sit in the build tree: a `build` link left there makes a recursive walk loop forever."""
        with tempfile.TemporaryDirectory() as folder:
            root = Path(folder)
            source, build = root / "src", root / "build"
            source.mkdir()
            (source / "README.md").write_text("```sh\ntest -L build\n```\n\n```sh\nfalse\n```\n")
            subprocess.run([sys.executable, str(RUNNER), "--source", str(source), "--build", str(build), "--cli",
                            "/bin/true", "--work", str(build / "docs_blocks"), "README.md"], capture_output=True)
            links = [p for p in (build / "docs_blocks").rglob("*") if p.is_symlink()]
            self.assertEqual(links, [])

    def test_files_no_command_names_fail(self):
        """README's `render clover_fractal.json -o clover.exr --png clover.png` also wrote clover_fractal.svg into
        the current folder (issue 32): a file left beside the repository's that no block names fails, naming it."""
        status, out = self.run_on("```sh\necho a > named.txt\nmkdir -p out && echo b > out/any.txt\n```\n")
        self.assertEqual(status, 0, out)
        status, out = self.run_on("```sh\necho a > named.txt\nn=2; echo b > side$n.svg\n```\n")
        self.assertEqual(status, 1, out)
        self.assertIn("README.md: its blocks left side2.svg in the folder they ran in, a file no command names; "
                      "write such outputs under out/ or name them", out)

    def test_a_failing_block_names_its_line_and_stderr(self):
        status, out = self.run_on("text\n\n```bash\ntrue\necho oops >&2; false\necho never\n```\n")
        self.assertEqual(status, 1, out)
        self.assertIn("README.md:3: bash block, exit status 1", out)
        self.assertIn("| oops", out)
        self.assertNotIn("never", out)

    def test_console_blocks_run_their_prompt_lines_only(self):
        status, out = self.run_on("```console\n$ echo one \\\n  two\none two\nthis line is output\n"
                                  "$ false || echo \"exit status $?\"\nexit status 1\n```\n")
        self.assertEqual(status, 0, out)

    def test_python_tracebacks_give_markdown_lines(self):
        status, out = self.run_on("# t\n\n```python\nx = 1\nraise ValueError('no')\n```\n", "--python-module", "/nonexistent")
        self.assertEqual(status, 1, out)
        self.assertIn('File "README.md", line 5', out)

    def test_python_blocks_need_the_module(self):
        status, out = self.run_on("```python\nraise SystemExit(3)\n```\n\n```sh\nPYTHONPATH=build/python python3 -c 1\n```\n")
        self.assertEqual(status, 0, out)
        self.assertIn("README.md:1 (python): the build has no Python module", out)
        self.assertIn("README.md:5 (sh): the build has no Python module", out)

    def test_marked_blocks_are_listed_with_their_reason(self):
        status, out = self.run_on("<!-- not run by tests: takes an hour -->\n```sh\nexit 1\n```\n\n```json\n{}\n```\n")
        self.assertEqual(status, 0, out)
        self.assertIn("skipped README.md:2 (sh): not run by tests: takes an hour", out)
        self.assertIn("0 blocks run", out)
        self.assertIn("1 marked not to run", out)
        self.assertIn("1 by language (1 json)", out)

    def test_malformed_fences_and_markers_fail(self):
        for markdown, message in [
                ("```\nls\n```\n", "README.md:1: the fence names no language"),
                ("```shell\nls\n```\n", "README.md:1: unknown fence language 'shell'"),
                ("```sh\n$ ls\n```\n", "README.md:1: a `$ ` prompt in an sh block"),
                ("```console\nls\n```\n", "README.md:1: a console block without a `$ ` command line"),
                ("<!-- not run by tests: -->\n```sh\nls\n```\n", "README.md:1: the not-run marker gives no reason"),
                ("<!-- not run by tests: slow -->\n\n```sh\nls\n```\n", "README.md:1: the not-run marker is not on"),
                ("<!-- not run by tests: slow -->\n```text\nls\n```\n", "README.md:2: a not-run marker on a text block"),
                ("```sh\nls\n", "README.md:1: the fence is never closed")]:
            with self.subTest(markdown=markdown):
                status, out = self.run_on(markdown)
                self.assertEqual(status, 1, out)
                self.assertIn(message, out)


if __name__ == "__main__":
    unittest.main()
