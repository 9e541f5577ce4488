from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["nubot_control", "nubot_control.ros"], package_dir={"": "src"},
                                 package_data={"nubot_control": ["py.typed"]}))
