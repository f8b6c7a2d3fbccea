"""Installing Debian packages that an experiment or benchmark script needs and the build does not
(blender, python3-openvdb, python3-matplotlib): never build or test dependencies."""
import os
import subprocess
import sys


def apt_install(packages, why):
    print(f"installing Debian's {' '.join(packages)} ({why})", file=sys.stderr)
    sudo = [] if os.geteuid() == 0 else ["sudo"]
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(sudo + ["apt-get", "install", "-y", "-qq", "--no-install-recommends"] + packages, check=True, env=env)
