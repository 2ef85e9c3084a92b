"""scripts/setup.sh waits for a package lock that another install holds (fake apt-get)."""

import os
import shutil
import subprocess

from conftest import ROOT


def fake_repo(tmp_path, locked_tries):
    # A copy of setup.sh in a repository whose venv is up to date (a stand-in python),
    # with dpkg-query saying one package is missing, and an apt-get whose install finds
    # the dpkg lock held `locked_tries` times (-1: always), as apt says it (and a sudo
    # that runs it, where the tests do not run as root).
    repo = tmp_path / "repo"
    (repo / "scripts").mkdir(parents=True)
    shutil.copy(os.path.join(ROOT, "scripts", "setup.sh"), repo / "scripts" / "setup.sh")
    (repo / "analysis").mkdir()
    for name, stamp in (("analysis/requirements.txt", ".venv/.requirements-installed"),
                        ("pyproject.toml", ".venv/.pyproject-installed")):
        (repo / name).write_text("same\n")
        (repo / stamp).parent.mkdir(exist_ok=True)
        (repo / stamp).write_text("same\n")
    bin_ = tmp_path / "bin"
    bin_.mkdir()
    scripts = {
        repo / ".venv" / "bin" / "python": "exit 0\n",
        # Not root: setup calls sudo, which would look apt-get up in its own PATH.
        bin_ / "sudo": 'exec "$@"\n',
        bin_ / "dpkg-query": '[ "$3" = clang-format ] && exit 1\necho "install ok installed"\n',
        bin_ / "apt-get": (
            '[ "$1" = update ] && exit 0\n'
            f'n=$(cat "{tmp_path}/tries" 2>/dev/null || echo 0); echo $((n + 1)) > '
            f'"{tmp_path}/tries"\n'
            f'if [ {locked_tries} -lt 0 ] || [ "$n" -lt {locked_tries} ]; then\n'
            '  echo "E: Could not get lock /var/lib/dpkg/lock-frontend. It is held by process'
            ' 1234 (apt-get)" >&2\n'
            '  echo "E: Unable to acquire the dpkg frontend lock (/var/lib/dpkg/lock-frontend),'
            ' is another process using it?" >&2\n  exit 100\nfi\n'
            f'echo installed > "{tmp_path}/installed"\n'),
    }
    for path, body in scripts.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("#!/bin/sh\n" + body)
        path.chmod(0o755)
    return repo, bin_


def run_setup(tmp_path, locked_tries, timeout):
    repo, bin_ = fake_repo(tmp_path, locked_tries)
    env = dict(os.environ, PATH=f"{bin_}:{os.environ['PATH']}",
               HRBENCH_APT_LOCK_TIMEOUT=str(timeout))
    return subprocess.run(["bash", str(repo / "scripts" / "setup.sh")], env=env,
                          capture_output=True, text=True, timeout=60)


def test_setup_waits_for_a_held_lock_saying_once_what_it_waits_for(tmp_path):
    r = run_setup(tmp_path, locked_tries=2, timeout=30)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "installed").exists()
    assert (tmp_path / "tries").read_text().strip() == "3"
    waits = [line for line in r.stderr.splitlines() if line.startswith("setup: waiting")]
    assert waits == ["setup: waiting up to 30 s (HRBENCH_APT_LOCK_TIMEOUT) for the package "
                     "lock /var/lib/dpkg/lock-frontend, held by process 1234 (apt-get)"]


def test_setup_gives_up_after_its_limit_with_one_line(tmp_path):
    r = run_setup(tmp_path, locked_tries=-1, timeout=3)
    assert r.returncode != 0
    assert not (tmp_path / "installed").exists()
    assert r.stderr.splitlines()[-1].startswith(
        "setup: gave up after 3 s waiting for the package lock /var/lib/dpkg/lock-frontend, "
        "held by process 1234 (apt-get); run again once the other install ends")
