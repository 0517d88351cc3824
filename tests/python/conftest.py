"""Paths of the built tools and the shared real meshes, passed by ctest (tests/CMakeLists.txt)
as environment variables; `vessel` itself is imported from the build tree (PYTHONPATH)."""

import os
import pathlib
import subprocess

import numpy as np
import pytest


def _env_path(name: str) -> pathlib.Path:
    value = os.environ.get(name)
    if not value:
        raise RuntimeError(f"{name} is not set; run these tests through ctest "
                           f"(ctest --test-dir build -L python)")
    return pathlib.Path(value)


@pytest.fixture(scope="session")
def flatten_exe() -> pathlib.Path:
    return _env_path("VESSEL_FLATTEN_EXE")


@pytest.fixture(scope="session")
def phantom_exe() -> pathlib.Path:
    return _env_path("VESSEL_PHANTOM_EXE")


@pytest.fixture(scope="session")
def real_data() -> pathlib.Path:
    path = _env_path("VESSEL_SHARED_DATA")
    assert path.is_dir(), f"the real meshes are expected in {path} (../shared/data/real)"
    return path


@pytest.fixture(scope="session")
def carotid(phantom_exe, tmp_path_factory) -> pathlib.Path:
    """The demo's carotid phantom (50% ICA stenosis), generated once."""
    path = tmp_path_factory.mktemp("phantom") / "carotid.ply"
    subprocess.run([str(phantom_exe), "carotid", "--stenosis", "0.5", "-o", str(path)],
                   check=True, capture_output=True)
    return path


def read_seam_obj(path: pathlib.Path):
    """The v, vt and f v/vt lines of vessel-flatten's seam-form OBJ (README.md)."""
    v, vt, fv, ft = [], [], [], []
    for line in path.read_text().splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            v.append([float(x) for x in parts[1:4]])
        elif parts[0] == "vt":
            vt.append([float(x) for x in parts[1:3]])
        elif parts[0] == "f":
            corners = [c.split("/") for c in parts[1:]]
            fv.append([int(c[0]) - 1 for c in corners])
            ft.append([int(c[1]) - 1 for c in corners])
    return np.array(v), np.array(vt), np.array(fv, dtype=np.int64), np.array(ft, dtype=np.int64)


def run_cli(flatten_exe, mesh, out, *flags):
    """vessel-flatten MESH -o OUT FLAGS; returns the finished process (not checked)."""
    return subprocess.run([str(flatten_exe), str(mesh), "-o", str(out), "--quiet", *flags],
                          capture_output=True, text=True)
