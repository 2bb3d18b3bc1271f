# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A sample user package: a controller that asks the wrenchcone node, and its tests."""

from setuptools import setup

PACKAGE = "my_tilt_controller"

setup(
    name=PACKAGE,
    version="0.2.0",
    packages=[PACKAGE],
    data_files=[("share/ament_index/resource_index/packages", [f"resource/{PACKAGE}"]),
                (f"share/{PACKAGE}", ["package.xml"])],
    install_requires=["setuptools"],
    zip_safe=True,
    description="A minimal controller that checks its wrench with the wrenchcone node",
    license="MIT",
    tests_require=["pytest"],
    entry_points={"console_scripts": [f"{PACKAGE} = {PACKAGE}.controller:main"]},
)
