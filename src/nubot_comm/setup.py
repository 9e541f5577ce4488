from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

# nubot_lcm: the LCM types, generated from lcm/*.lcm by lcm-gen and kept in the repository.
setup(**generate_distutils_setup(packages=["nubot_comm", "nubot_comm.ros", "nubot_lcm"], package_dir={"": "src"}))
