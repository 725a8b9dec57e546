"""Write the four example meshes of ``taxelkit.learn.examples`` as STL files beside this script.

Run from the repository root: ``python examples/objects/make_objects.py``.
``tests/learn/test_examples.py`` checks the committed files against the code.
"""

from __future__ import annotations

from pathlib import Path

from taxelkit.learn.examples import EXAMPLE_OBJECTS, example_mesh


def main() -> None:
    """Write ``NAME.stl`` (binary, mm) for every example object."""
    here = Path(__file__).resolve().parent
    for name in EXAMPLE_OBJECTS:
        example_mesh(name).export(here / f"{name}.stl")


if __name__ == "__main__":
    main()
