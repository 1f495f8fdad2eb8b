"""The Blender script's file rules, without Blender: the same rules as the
analyzer's file layer (regular files only, no hang on a FIFO, size caps, links
resolved before the containment check, nothing written through a link or over
an existing file). Run: python3 scripts/blender/test_ufcsr_blender.py"""

import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ufcsr_blender as script  # noqa: E402  (bpy is imported only where rendering needs it)


class FileRules(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory()
        self.archive = os.path.join(self.folder.name, "archive")
        os.mkdir(self.archive)

    def tearDown(self):
        self.folder.cleanup()

    def manifest_path(self):
        return os.path.join(self.archive, "manifest.json")

    def test_a_fifo_manifest_is_refused_without_hanging(self):
        os.mkfifo(self.manifest_path())
        with self.assertRaisesRegex(script.InputError, "manifest.json: not a regular file"):
            script.read_manifest(self.archive)

    def test_a_manifest_linked_to_dev_zero_is_refused(self):
        os.symlink("/dev/zero", self.manifest_path())
        with self.assertRaisesRegex(script.InputError, "not a regular file"):
            script.read_manifest(self.archive)

    def test_a_huge_manifest_is_refused_by_its_size(self):
        with open(self.manifest_path(), "wb") as file:
            file.truncate(script.MANIFEST_LIMIT + 1)
        with self.assertRaisesRegex(script.InputError, "bytes allowed"):
            script.read_manifest(self.archive)

    def test_a_named_file_linked_outside_the_archive_is_refused(self):
        os.symlink("/etc/passwd", os.path.join(self.archive, "parts.csv"))
        with self.assertRaisesRegex(script.InputError, "outside the archive.*through a link"):
            script.inside(self.archive, "parts.csv", self.manifest_path())

    def test_a_named_file_that_is_a_fifo_is_refused(self):
        os.mkfifo(os.path.join(self.archive, "pidt.png"))
        with self.assertRaisesRegex(script.InputError, "not a regular file"):
            script.inside(self.archive, "pidt.png", self.manifest_path())

    def test_the_output_is_never_a_link_nor_a_full_folder(self):
        target = os.path.join(self.folder.name, "elsewhere")
        os.mkdir(target)
        link = os.path.join(self.folder.name, "out")
        os.symlink(target, link)
        with self.assertRaisesRegex(script.InputError, "is a link"):
            script.prepare_out(self.archive, link)
        with open(os.path.join(target, "keep.txt"), "w") as file:
            file.write("x")
        with self.assertRaisesRegex(script.InputError, "not an empty folder"):
            script.prepare_out(self.archive, target)

    def test_files_are_written_new_never_over_or_through_anything(self):
        path = os.path.join(self.folder.name, "new.png")
        script.write_new(path, b"one")
        with self.assertRaises(FileExistsError):
            script.write_new(path, b"two")
        os.symlink("/dev/null", os.path.join(self.folder.name, "link.png"))
        with self.assertRaises(OSError):
            script.write_new(os.path.join(self.folder.name, "link.png"), b"x")
        with open(path, "rb") as file:
            self.assertEqual(file.read(), b"one")

    def test_copied_files_come_from_inside_the_archive(self):
        with open(os.path.join(self.archive, "pidt.png"), "wb") as file:
            file.write(b"pidt")
        for name in ("vehicle.glb", "scene.glb"):
            with open(os.path.join(self.archive, name), "wb") as file:
                file.write(b"glb")
        os.symlink("/etc/passwd", os.path.join(self.archive, "parts.csv"))
        manifest = {"pidt": "pidt.png", "parts": "parts.csv", "vehicle": "vehicle.glb", "occluders": "scene.glb"}
        out = os.path.join(self.folder.name, "copy")
        os.mkdir(out)
        with self.assertRaisesRegex(script.InputError, "outside the archive"):
            script.copy_described_files(self.archive, out, manifest)
        self.assertFalse(os.path.exists(os.path.join(out, "parts.csv")))


if __name__ == "__main__":
    unittest.main()
