from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["nubot_tools", "nubot_tools.bench", "nubot_tools.report", "nubot_tools.ros"],
                                 package_dir={"": "src"}))
