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
import fbx_to_glb  # noqa: E402  (the same: bpy only inside convert)
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

    def test_a_deeply_nested_manifest_is_refused_naming_the_file(self):
        with open(self.manifest_path(), "w") as file:
            file.write("[" * 100_000 + "]" * 100_000)
        with self.assertRaisesRegex(script.InputError, "manifest.json: not readable JSON"):
            script.read_manifest(self.archive)

    def test_a_corrupt_fbx_is_refused_naming_the_file_not_a_traceback(self):
        class Refusing:
            def fbx(self, **_):
                raise RuntimeError("Error: ASCII FBX files are not supported")

        class Ops:
            import_scene = Refusing()

            class wm:
                @staticmethod
                def read_factory_settings(use_empty):
                    return {"FINISHED"}

        class Units:
            system = None
            scale_length = None

        class Scene:
            unit_settings = Units()
            objects = []

        class FakeBpy:
            ops = Ops()

            class context:
                scene = Scene()

        with self.assertRaisesRegex(fbx_to_glb.InputError, "corrupt.fbx: Blender's FBX importer could not read it"):
            fbx_to_glb.import_fbx(FakeBpy(), "corrupt.fbx")

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

    def described(self, **changes):
        for name in ("pidt.png", "parts.csv", "vehicle.glb", "scene.glb"):
            if not os.path.lexists(os.path.join(self.archive, name)):
                with open(os.path.join(self.archive, name), "wb") as file:
                    file.write(b"x")
        manifest = {"pidt": "pidt.png", "parts": "parts.csv", "vehicle": "vehicle.glb", "occluders": "scene.glb"}
        manifest.update(changes)
        return script.described_files(self.archive, manifest)

    def test_the_vehicle_and_occluders_are_checked_before_blender_imports_them(self):
        # A FIFO vehicle.glb used to hang Blender's importer; a link to /dev/zero to fill the memory.
        os.mkfifo(os.path.join(self.archive, "vehicle.glb"))
        with self.assertRaisesRegex(script.InputError, "vehicle.glb.*not a regular file"):
            self.described()
        os.remove(os.path.join(self.archive, "vehicle.glb"))
        os.remove(os.path.join(self.archive, "scene.glb"))
        os.symlink("/dev/zero", os.path.join(self.archive, "scene.glb"))
        with self.assertRaisesRegex(script.InputError, "scene.glb"):
            self.described()
        os.remove(os.path.join(self.archive, "scene.glb"))
        with self.assertRaisesRegex(script.InputError, "leaves the archive"):
            self.described(vehicle="../archive/vehicle.glb")
        with self.assertRaisesRegex(script.InputError, "'occluders' does not name a file"):
            self.described(occluders=None)
        found = self.described()
        self.assertEqual(found["vehicle.glb"], os.path.realpath(os.path.join(self.archive, "vehicle.glb")))

    def test_a_described_file_over_the_cap_is_refused_by_its_size(self):
        with open(os.path.join(self.archive, "pidt.png"), "wb") as file:
            file.truncate(script.COPIED_FILE_LIMIT + 1)
        with self.assertRaisesRegex(script.InputError, "pidt.png: .* bytes allowed"):
            self.described()

    def test_save_blend_never_replaces_a_link_a_fifo_or_an_input(self):
        out = os.path.join(self.folder.name, "out")
        fifo = os.path.join(self.folder.name, "scene.blend")
        os.mkfifo(fifo)
        with self.assertRaisesRegex(script.InputError, "not a regular file"):
            script.refuse_save_blend(fifo, self.archive, out)
        link = os.path.join(self.folder.name, "link.blend")
        os.symlink("/dev/null", link)
        with self.assertRaisesRegex(script.InputError, "link"):
            script.refuse_save_blend(link, self.archive, out)
        with self.assertRaisesRegex(script.InputError, "inside the source archive"):
            script.refuse_save_blend(os.path.join(self.archive, "set-up.blend"), self.archive, out)
        with self.assertRaisesRegex(script.InputError, "inside --out"):
            script.refuse_save_blend(os.path.join(out, "set-up.blend"), self.archive, out)
        script.refuse_save_blend(os.path.join(self.folder.name, "fine.blend"), self.archive, out)


class FbxToGlbRules(unittest.TestCase):
    """fbx_to_glb.py renames its outputs into place: never over a device, FIFO or link, never the input."""

    def setUp(self):
        self.folder = tempfile.TemporaryDirectory()
        self.fbx = os.path.join(self.folder.name, "car.fbx")
        with open(self.fbx, "wb") as file:
            file.write(b"fbx")

    def tearDown(self):
        self.folder.cleanup()

    def path(self, name):
        return os.path.join(self.folder.name, name)

    def test_an_output_that_is_a_fifo_a_device_link_or_the_input_is_refused(self):
        os.mkfifo(self.path("out.glb"))
        with self.assertRaisesRegex(fbx_to_glb.InputError, "out.glb: is not a regular file"):
            fbx_to_glb.check_paths(self.fbx, self.path("out.glb"), self.path("r.json"))
        os.symlink("/dev/null", self.path("null.glb"))
        with self.assertRaisesRegex(fbx_to_glb.InputError, "is a link"):
            fbx_to_glb.check_paths(self.fbx, self.path("null.glb"), self.path("r.json"))
        os.mkfifo(self.path("r.json"))
        with self.assertRaisesRegex(fbx_to_glb.InputError, "r.json: is not a regular file"):
            fbx_to_glb.check_paths(self.fbx, self.path("new.glb"), self.path("r.json"))
        with self.assertRaisesRegex(fbx_to_glb.InputError, "report would replace the model"):
            fbx_to_glb.check_paths(self.fbx, self.path("new.glb"), self.path("new.glb"))
        fbx_to_glb.check_paths(self.fbx, self.path("new.glb"), self.path("new.report.json"))

    def test_the_input_is_a_regular_file_within_the_cap(self):
        os.symlink("/dev/zero", self.path("zero.fbx"))
        with self.assertRaisesRegex(fbx_to_glb.InputError, "zero.fbx: not a regular file"):
            fbx_to_glb.check_paths(self.path("zero.fbx"), self.path("new.glb"), self.path("r.json"))
        with open(self.fbx, "wb") as file:
            file.truncate(fbx_to_glb.FBX_LIMIT + 1)
        with self.assertRaisesRegex(fbx_to_glb.InputError, "car.fbx: .* bytes allowed"):
            fbx_to_glb.check_paths(self.fbx, self.path("new.glb"), self.path("r.json"))


if __name__ == "__main__":
    unittest.main()
