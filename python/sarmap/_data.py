"""The data sarmap ships (the DGCNN model, the arenas), found as the sarmap
binary finds it (tools/sarmap/shipped_data.cpp): in SARMAP_DATA_DIR when it is
set, and only there; otherwise beside the installed package (PREFIX/share/sarmap)
or, for the package in the build tree, in the source tree's datasets/."""

import os

from . import _data_paths


def data_dirs():
    """The folders searched for shipped data, in order, as (path, why) pairs."""
    env = os.environ.get("SARMAP_DATA_DIR")
    if env:
        return [(env, "from SARMAP_DATA_DIR")]
    return [(os.path.normpath(_data_paths.DATA_DIR), _data_paths.DATA_DIR_WHY)]


def shipped_file(relative):
    """The first data folder's `relative` file; FileNotFoundError lists every place looked."""
    looked = []
    for folder, why in data_dirs():
        path = os.path.join(folder, relative)
        if os.path.isfile(path):
            return path
        looked.append(f"{path}, {why}")
    raise FileNotFoundError(
        f"the shipped {relative} was not found (looked for {'; '.join(looked)}); "
        "point SARMAP_DATA_DIR at a folder holding models/ and arenas/")


def shipped_model():
    """models/ramps-dgcnn.safetensors: the model a dgcnn config without "model" uses."""
    return shipped_file(os.path.join("models", "ramps-dgcnn.safetensors"))


def shipped_arena(name="esogu-6x4"):
    """arenas/NAME.json, one of the arenas sarmap ships (the default one by default)."""
    return shipped_file(os.path.join("arenas", name + ".json"))
