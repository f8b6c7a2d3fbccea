"""Installing Debian packages that an experiment or benchmark script needs and the build does not
(blender, python3-openvdb, python3-matplotlib): never build or test dependencies."""
import os
import shutil
import subprocess
import sys


def apt_install(packages, why):
    print(f"installing Debian's {' '.join(packages)} ({why})", file=sys.stderr)
    sudo = [] if os.geteuid() == 0 else ["sudo"]
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(sudo + ["apt-get", "install", "-y", "-qq", "--no-install-recommends"] + packages, check=True, env=env)


def run_plot_script(name, args):
    """Runs scripts/NAME with Debian's python3, installing python3-matplotlib first if it is missing."""
    if subprocess.run(["/usr/bin/python3", "-c", "import matplotlib"], capture_output=True).returncode != 0:
        apt_install(["python3-matplotlib"], "for the plot")
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    subprocess.run(["/usr/bin/python3", script] + [str(a) for a in args], check=True, text=True, capture_output=True)


def ensure_blender(why="benchmark only"):
    """Debian's blender (the peer renderer, and the EXR reader of the experiment scripts)."""
    if not shutil.which("blender"):
        apt_install(["blender"], why)
    return shutil.which("blender") is not None
