# SPDX-License-Identifier: MIT
"""The package itself: submodules, error types, version, docstrings everywhere."""
import inspect
import unittest

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

    def test_docs_name_every_public_object(self):
        text = (SOURCE_DIR / "docs" / "python.md").read_text()
        missing = [f"cifs.{name}.{attr}" for name in SUBMODULES for attr in vars(getattr(cifs, name))
                   if not attr.startswith("_") and f"`{attr}`" not in text and f"`{attr}(" not in text]
        self.assertEqual(missing, [], "public objects that docs/python.md does not name")


if __name__ == "__main__":
    unittest.main()
