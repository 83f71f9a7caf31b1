#!/usr/bin/python3
"""`pip install -e python` works offline with Debian's pip and setuptools (docs/python.md "Setup").
Installs a copy of python/ into a throw-away venv that sees the system's packages (numpy), so
neither the tree nor the system Python changes. Run by ctest (PythonInstall); exits 77 (skip)
without python3-venv or pip."""
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    missing = [m for m in ("ensurepip", "pip", "setuptools", "venv", "wheel")
               if importlib.util.find_spec(m) is None]
    if missing:
        print("skipped: no %s (apt-get install python3-venv python3-pip python3-wheel)" %
              ", ".join(missing))
        return 77
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "python")
        shutil.copytree(os.path.join(REPO, "python"), src,
                        ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "tests"))
        env_dir = os.path.join(tmp, "venv")
        subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip",
                        env_dir], check=True)
        py = os.path.join(env_dir, "bin", "python")
        # The venv has no pip of its own: the system's pip installs into it (--python needs pip
        # >= 22.3; Debian 12 has 23.0).
        r = subprocess.run([sys.executable, "-m", "pip", "--python", py, "install", "--no-build-isolation",
                            "--no-index", "--quiet", "-e", src],
                           capture_output=True, text=True, cwd=tmp)
        if r.returncode != 0:
            print(r.stdout + r.stderr)
            print("FAIL: pip install -e python")
            return 1
        r = subprocess.run([py, "-c", "import fovsim; print(fovsim.__file__)"], capture_output=True,
                           text=True, cwd=tmp)
        where = r.stdout.strip()
        if r.returncode != 0 or not where.startswith(os.path.join(src, "fovsim")):
            print(r.stdout + r.stderr)
            print("FAIL: the installed fovsim is not the editable copy (%s)" % where)
            return 1
        print("OK: editable install at", where)
    return 0


if __name__ == "__main__":
    sys.exit(main())
