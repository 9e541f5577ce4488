"""The message contract: every type's md5sum is in md5sums.txt, and the original NuBot types keep theirs.

ROS 1 connects a publisher and a subscriber only when their md5sums agree, and the md5sum follows the
field names, types and order. ``original_msgs/`` holds the original nubot_common package's definitions
(fields only); a node built against that package talks to ours exactly where the md5sums below agree.
"""

from pathlib import Path

import genmsg
import genmsg.msg_loader as loader
import pytest
import rospkg

import nubot_common.msg as msgs
import nubot_common.srv as srvs

PACKAGE = Path(__file__).resolve().parents[1]
ORIGINAL = Path(__file__).resolve().parent / "original_msgs"
TABLE = Path(__file__).resolve().parent / "md5sums.txt"
# The original spells one type differently; the md5sum does not include the type's own name.
OUR_NAME = {"OminiVisionInfo": "OmniVisionInfo"}
# Where the chapter defines a type differently from the original code, the chapter decides.
CHAPTER_DIFFERS = {"Shoot": "the chapter's Table 3 has int64 strength; the original code float32"}


def read_table() -> dict[str, tuple[str, str]]:
    rows = {}
    for line in TABLE.read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            name, md5, origin = line.split()
            rows[name] = (md5, origin)
    return rows


def original_md5(path: Path) -> str:
    """The md5sum genmsg computes for an original definition, resolving its nested types among the originals."""
    context = loader.MsgContext.create_default()
    search = {"nubot_common": [str(ORIGINAL)], "std_msgs": [str(Path(rospkg.RosPack().get_path("std_msgs")) / "msg")]}
    if path.suffix == ".srv":
        spec = loader.load_srv_by_type(context, f"nubot_common/{path.stem}", search)
        loader.load_depends(context, spec.request, search)
        loader.load_depends(context, spec.response, search)
    else:
        spec = loader.load_msg_by_type(context, f"nubot_common/{path.stem}", search)
        loader.load_depends(context, spec, search)
    return genmsg.compute_md5(context, spec)


ALL_TYPES = [f"msg/{p.stem}" for p in sorted((PACKAGE / "msg").glob("*.msg"))] + \
            [f"srv/{p.stem}" for p in sorted((PACKAGE / "srv").glob("*.srv"))]
ORIGINALS = sorted([*ORIGINAL.glob("*.msg"), *ORIGINAL.glob("*.srv")])


def test_the_table_lists_every_type_of_the_package_and_nothing_else():
    assert sorted(read_table()) == sorted(ALL_TYPES)


@pytest.mark.parametrize("name", ALL_TYPES)
def test_generated_md5sum_is_the_one_in_the_table(name):
    kind, type_name = name.split("/")
    generated = getattr(msgs if kind == "msg" else srvs, type_name)._md5sum
    assert generated == read_table()[name][0], f"{name} changed its md5sum: update md5sums.txt only on purpose"


@pytest.mark.parametrize("path", ORIGINALS, ids=[p.stem for p in ORIGINALS])
def test_every_original_type_has_the_original_md5sum(path):
    name = f"{'srv' if path.suffix == '.srv' else 'msg'}/{OUR_NAME.get(path.stem, path.stem)}"
    md5, origin = read_table()[name]
    if path.stem in CHAPTER_DIFFERS:
        assert md5 != original_md5(path), CHAPTER_DIFFERS[path.stem]
        assert origin == "chapter"
    else:
        assert md5 == original_md5(path), f"{name} no longer interoperates with the original nubot_common"
        assert origin in ("original", "chapter")


def test_types_marked_original_or_chapter_exist_in_the_original_package():
    originals = {OUR_NAME.get(p.stem, p.stem) for p in ORIGINALS}
    marked = {name.split("/")[1] for name, (_, origin) in read_table().items() if origin != "ours"}
    assert marked == originals


def test_an_original_node_and_ours_share_the_md5sum_on_the_wire():
    """The md5sum a subscriber built from the original WorldModelInfo sends equals what our publisher offers."""
    assert original_md5(ORIGINAL / "WorldModelInfo.msg") == msgs.WorldModelInfo._md5sum
    assert original_md5(ORIGINAL / "OminiVisionInfo.msg") == msgs.OmniVisionInfo._md5sum
