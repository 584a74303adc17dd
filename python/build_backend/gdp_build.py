"""PEP 517 build backend for gdp's Python module: CMake builds it, this writes the wheel.

Only the standard library is used and nothing is downloaded, so `pip install .` works offline
with Debian's packages (pyproject.toml: requires = [], backend-path = ["python/build_backend"]).
Config settings (pip install . --config-settings KEY=VALUE):
  build-dir=DIR  build in DIR and keep it (default: a temporary directory, removed afterwards);
                 an existing gdp build tree there is reused (only the module's targets are built)
  jobs=N         parallel build jobs (default: all cores)
CMAKE_CXX_COMPILER_LAUNCHER=ccache in the environment speeds up rebuilds.
"""

import base64
import hashlib
import io
import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import tempfile
import tomllib
import zipfile

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _project():
    with open(ROOT / "pyproject.toml", "rb") as f:
        project = tomllib.load(f)["project"]
    cmake = (ROOT / "CMakeLists.txt").read_text()
    project["version"] = re.search(r"project\(gdp VERSION ([0-9.]+)", cmake).group(1)
    return project


def _metadata(project):
    lines = [
        "Metadata-Version: 2.1",
        f"Name: {project['name']}",
        f"Version: {project['version']}",
        f"Summary: {project['description']}",
        f"Requires-Python: {project['requires-python']}",
    ]
    lines += [f"Requires-Dist: {d}" for d in project.get("dependencies", [])]
    return "\n".join(lines) + "\n"


def _tag():
    interpreter = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{interpreter}-{interpreter}{sys.abiflags}-{platform}"


def _dist_info(project):
    return f"{project['name']}-{project['version']}.dist-info"


def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    project = _project()
    info = pathlib.Path(metadata_directory) / _dist_info(project)
    info.mkdir(parents=True, exist_ok=True)
    (info / "METADATA").write_text(_metadata(project))
    return info.name


def _cmake(build, jobs):
    """Configures (unless `build` holds a gdp build tree already) and builds the module's targets."""
    if not (build / "CMakeCache.txt").exists():
        generator = ["-G", "Ninja"] if shutil.which("ninja") else []
        # A static libgdp: the extension holds the library, nothing to find at run time.
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), *generator, "-DCMAKE_BUILD_TYPE=Release",
                        "-DGDP_BUILD_TESTS=OFF", "-DGDP_BUILD_BENCH=OFF", "-DGDP_BUILD_PYTHON=ON",
                        "-DBUILD_SHARED_LIBS=OFF",
                        f"-DPython_EXECUTABLE={sys.executable}"], check=True, stdout=sys.stderr)
    subprocess.run(["cmake", "--build", str(build), "--target", "gdp_python", "gdp_oiio", "--parallel", str(jobs)],
                   check=True, stdout=sys.stderr)


def _record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    settings = config_settings or {}
    project = _project()
    jobs = int(settings.get("jobs", os.cpu_count() or 1))
    keep = settings.get("build-dir")
    build = pathlib.Path(keep).resolve() if keep else pathlib.Path(tempfile.mkdtemp(prefix="gdp-wheel-"))
    try:
        _cmake(build, jobs)
        # The compiled files, listed by CMake (python/CMakeLists.txt), all beside gdp/__init__.py:
        # the OpenImageIO module is looked for beside the code, libgdp.so through RPATH $ORIGIN.
        files = {"gdp/__init__.py": ROOT / "python" / "gdp" / "__init__.py"}
        for line in (build / "python" / "wheel_files.txt").read_text().split():
            files[f"gdp/{pathlib.Path(line).name}"] = pathlib.Path(line)
        info = _dist_info(project)
        generated = {
            f"{info}/METADATA": _metadata(project),
            f"{info}/WHEEL": f"Wheel-Version: 1.0\nGenerator: gdp_build\nRoot-Is-Purelib: false\nTag: {_tag()}\n",
            f"{info}/top_level.txt": "gdp\n",
        }
        name = f"{project['name']}-{project['version']}-{_tag()}.whl"
        record = []
        with zipfile.ZipFile(pathlib.Path(wheel_directory) / name, "w", zipfile.ZIP_DEFLATED) as wheel:
            for arcname, path in files.items():
                data = path.read_bytes()  # through symbolic links (libgdp.so.SONAME)
                info_entry = zipfile.ZipInfo(arcname)
                info_entry.external_attr = (0o755 if arcname.endswith(".so") else 0o644) << 16
                info_entry.compress_type = zipfile.ZIP_DEFLATED
                wheel.writestr(info_entry, data)
                record.append(_record_line(arcname, data))
            for arcname, text in generated.items():
                wheel.writestr(arcname, text)
                record.append(_record_line(arcname, text.encode()))
            record.append(f"{info}/RECORD,,")
            wheel.writestr(f"{info}/RECORD", "\n".join(record) + "\n")
        return name
    finally:
        if not keep:
            shutil.rmtree(build, ignore_errors=True)


def build_sdist(sdist_directory, config_settings=None):
    """The files git tracks (or, outside a git checkout, the tree without build outputs)."""
    project = _project()
    base = f"{project['name']}-{project['version']}"
    try:
        listed = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], check=True, capture_output=True).stdout
        names = [n for n in listed.decode().split("\0") if n]
    except (OSError, subprocess.CalledProcessError):
        skip = {"build", "out", ".git"}
        names = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*")
                 if p.is_file() and p.relative_to(ROOT).parts[0] not in skip]
    name = f"{base}.tar.gz"
    with tarfile.open(pathlib.Path(sdist_directory) / name, "w:gz") as sdist:
        for n in names:
            sdist.add(ROOT / n, arcname=f"{base}/{n}", recursive=False)
        pkg_info = _metadata(project).encode()
        entry = tarfile.TarInfo(f"{base}/PKG-INFO")
        entry.size = len(pkg_info)
        sdist.addfile(entry, io.BytesIO(pkg_info))
    return name
