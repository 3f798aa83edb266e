# SPDX-License-Identifier: MIT
"""The package itself: submodules, error types, version, docstrings everywhere."""
import inspect
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import cifs
from support import SOURCE_DIR

SUBMODULES = ("nurbs", "automata", "ifs", "subdivision", "render", "io", "verify", "experiment")


class PackageTest(unittest.TestCase):
    def test_submodules_import_like_package_modules(self):
        import importlib
        for name in SUBMODULES:
            self.assertIs(importlib.import_module(f"cifs.{name}"), getattr(cifs, name))

    def test_error_types(self):
        self.assertTrue(issubclass(cifs.InvalidInput, ValueError))
        self.assertTrue(issubclass(cifs.IoError, OSError))

    def test_version_is_the_project_version(self):
        text = (SOURCE_DIR / "CMakeLists.txt").read_text()
        self.assertIn(f"project(cifs VERSION {cifs.__version__} ", text)

    def test_signatures_name_python_types_not_cpp_ones(self):
        """A type registered after a function that takes it shows as its C++ name (`cifs::Mesh`) in the
        signature, pydoc and the stubs (where it became `Any`)."""
        import re
        leaks = []
        for name in SUBMODULES:
            for attr, obj in vars(getattr(cifs, name)).items():
                members = [(attr, obj)] + ([(f"{attr}.{m}", v) for m, v in vars(obj).items()]
                                           if inspect.isclass(obj) else [])
                # A property's signatures are its getter's and setter's docstrings (FractalFit.file showed
                # `-> cifs::io::BcifsFile`).
                members += [(f"{where}.{part}", getattr(value, part)) for where, value in members
                            if isinstance(value, property) for part in ("fget", "fset") if getattr(value, part)]
                for where, value in members:
                    found = re.findall(r"\bcifs::[\w:]+", getattr(value, "__doc__", None) or "")
                    leaks += [f"cifs.{name}.{where}: {t}" for t in sorted(set(found))]
        self.assertEqual(leaks, [])

    def test_every_public_object_has_a_docstring(self):
        missing = []
        for name in SUBMODULES:
            module = getattr(cifs, name)
            for attr, obj in vars(module).items():
                if attr.startswith("_"):
                    continue
                if not (obj.__doc__ or "").strip():
                    missing.append(f"cifs.{name}.{attr}")
                if inspect.isclass(obj):
                    for member, value in vars(obj).items():
                        if member.startswith("_") or not callable(value) and not isinstance(value, property):
                            continue
                        if not (getattr(value, "__doc__", "") or "").strip():
                            missing.append(f"cifs.{name}.{attr}.{member}")
        self.assertEqual(missing, [], "objects without a docstring")

    def test_surface_closest_points_regions_docstring_reads_as_one_line(self):
        """A stray "a\\n" between two C++ literals broke it inside "the centre of a sphere"."""
        doc = cifs.nurbs.SurfaceClosestPoints.regions.__doc__
        self.assertIn("(the centre of a sphere: the whole domain;", doc)
        self.assertNotIn("\n", doc)

    def test_docs_name_every_public_object(self):
        text = (SOURCE_DIR / "docs" / "python.md").read_text()
        missing = [f"cifs.{name}.{attr}" for name in SUBMODULES for attr in vars(getattr(cifs, name))
                   if not attr.startswith("_") and f"`{attr}`" not in text and f"`{attr}(" not in text]
        self.assertEqual(missing, [], "public objects that docs/python.md does not name")



class InterpreterTest(unittest.TestCase):
    """build/cifs-python runs the build's interpreter; another interpreter is told to use it."""

    def setUp(self):
        self.package = Path(cifs.__file__).resolve().parent  # build/python/cifs (ctest's PYTHONPATH)
        self.env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}

    def test_the_launcher_runs_the_build_interpreter_with_the_package(self):
        launcher = self.package.parents[1] / "cifs-python"
        self.assertTrue(os.access(launcher, os.X_OK), launcher)
        with tempfile.TemporaryDirectory() as folder:  # from anywhere, without PYTHONPATH
            run = subprocess.run([str(launcher), "-c", "import cifs, sys; print(cifs.__version__, sys.executable)"],
                                 cwd=folder, env=self.env, capture_output=True, text=True, check=True)
        version, executable = run.stdout.split()
        self.assertEqual(version, cifs.__version__)
        self.assertEqual(Path(executable).resolve(), Path(sys.executable).resolve())

    def test_an_extension_for_another_interpreter_names_the_launcher(self):
        with tempfile.TemporaryDirectory() as folder:
            copy = Path(folder) / "cifs"
            copy.mkdir()
            shutil.copy(self.package / "__init__.py", copy)
            (copy / "_cifs.cpython-39-x86_64-linux-gnu.so").write_bytes(b"")  # built for another Python
            run = subprocess.run([sys.executable, "-c", "import cifs"], cwd=folder, env=dict(self.env, PYTHONPATH=folder),
                                 capture_output=True, text=True)
        self.assertNotEqual(run.returncode, 0)
        self.assertIn("_cifs.cpython-39-x86_64-linux-gnu.so does not load in this interpreter", run.stderr)
        self.assertIn("Run scripts with build/cifs-python", run.stderr)

    def test_an_extension_not_built_names_the_command_that_builds_it(self):
        with tempfile.TemporaryDirectory() as folder:
            build = Path(folder) / "build"
            copy = build / "python" / "cifs"
            copy.mkdir(parents=True)
            shutil.copy(self.package / "__init__.py", copy)  # configured, the extension not built
            run = subprocess.run([sys.executable, "-c", "import cifs"], cwd=folder,
                                 env=dict(self.env, PYTHONPATH=str(build / "python")), capture_output=True, text=True)
        self.assertNotEqual(run.returncode, 0)
        self.assertIn(f"the extension cifs._cifs is not built: cmake --build {build} --target cifs_python", run.stderr)
        self.assertNotIn("Run scripts with build/cifs-python", run.stderr)

    def test_the_gallery_preset_builds_what_the_readme_runs_next(self):
        """README: `cmake --workflow --preset gallery`, then build/apps/cifs … and build/cifs-python …"""
        import json
        presets = json.loads((SOURCE_DIR / "CMakePresets.json").read_text())
        workflow = next(w for w in presets["workflowPresets"] if w["name"] == "gallery")
        builds = {b["name"]: b for b in presets["buildPresets"]}
        targets = {t for step in workflow["steps"] if step["type"] == "build" for t in builds[step["name"]]["targets"]}
        self.assertLessEqual({"cifs_cli", "cifs_python", "gallery"}, targets)


if __name__ == "__main__":
    unittest.main()
