from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["world_model", "world_model.ros"], package_dir={"": "src"},
                                 package_data={"world_model": ["py.typed"]}))
