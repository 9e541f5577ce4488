from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["coach4sim", "coach4sim.ros"], package_dir={"": "src"},
                                  package_data={"coach4sim": ["viewer_assets/*"]}))
