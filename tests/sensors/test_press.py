"""The press pipeline: sampling, element averaging, chunking, seeding, active block."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.sensors import OPTICAL_3AXIS
from taxelkit.sensors.press import displacement_from_relief, sample_offsets_mm
from taxelkit.world.base import Relief


@dataclass(frozen=True)
class HalfPlaneStep:
    """Raised by ``step_mm`` where ``x > x0_mm``."""

    x0_mm: float = 0.0
    step_mm: float = 0.05

    def height_mm(self, x_mm: Any, y_mm: Any) -> Any:
        return np.where(np.asarray(x_mm) > self.x0_mm, self.step_mm, 0.0) + 0.0 * y_mm


def test_custom_relief_satisfies_the_protocol() -> None:
    assert isinstance(HalfPlaneStep(), Relief)


def test_sample_offsets_cover_each_element_symmetrically() -> None:
    x, y = sample_offsets_mm(OPTICAL_3AXIS.array, margin=0, oversample=3)
    assert x.shape == (13 * 3,) and y.shape == (10 * 3,)
    per_element = x.reshape(13, 3)
    np.testing.assert_allclose(per_element.mean(axis=1), (np.arange(13) - 6) * 3.0)
    np.testing.assert_allclose(np.ptp(per_element, axis=1), 2 / 3)  # 1 mm element, 3 samples
    with pytest.raises(InputError, match="oversample"):
        sample_offsets_mm(OPTICAL_3AXIS.array, margin=0, oversample=0)


def test_step_under_half_the_array_separates_the_halves() -> None:
    step, indent = 0.05, 0.1
    u = displacement_from_relief(
        OPTICAL_3AXIS, HalfPlaneStep(0.0, step), [0.0, 0.0], indent_mm=indent, add_noise=False,
        dtype=np.float64,
    )[0]  # fmt: skip
    np.testing.assert_allclose(u[:, :5], indent, atol=1e-12)  # x <= -3 mm
    np.testing.assert_allclose(u[:, 7:], indent + step, atol=1e-12)  # x >= +3 mm
    assert indent <= u[0, 6] <= indent + step  # the column on the edge is in between


def test_element_average_grades_the_step_as_it_crosses_an_element() -> None:
    xs = np.linspace(-0.6, 0.6, 13)  # move the edge across the centre column's element
    pos = np.stack([-xs, np.zeros_like(xs)], axis=1)  # edge at x=0 in world -> -x in array
    u = displacement_from_relief(
        OPTICAL_3AXIS, HalfPlaneStep(), pos, indent_mm=0.1, add_noise=False, oversample=9,
        dtype=np.float64,
    )[:, 5, 6]  # fmt: skip
    assert np.all(np.diff(u) <= 1e-12)  # as the array moves right the centre taxel leaves the step
    assert u[0] == pytest.approx(0.15) and u[-1] == pytest.approx(0.1, abs=0.002)


def test_active_only_equals_the_cropped_full_frame() -> None:
    pos = np.array([[1.3, -0.7], [4.0, 2.0]])
    kw: dict[str, Any] = {"indent_mm": 0.1, "add_noise": False, "yaw_deg": [0.0, 30.0]}
    full = displacement_from_relief(OPTICAL_3AXIS, HalfPlaneStep(), pos, **kw)
    block = displacement_from_relief(OPTICAL_3AXIS, HalfPlaneStep(), pos, active_only=True, **kw)
    rows, cols = OPTICAL_3AXIS.array.active_region.slices
    assert block.shape == (2, 6, 6)
    np.testing.assert_array_equal(block, full[:, rows, cols])


def test_same_seed_same_frames_and_chunking_does_not_matter() -> None:
    pos = np.random.default_rng(0).uniform(-5, 5, size=(37, 2))
    kw: dict[str, Any] = {"indent_mm": 0.1, "rng": 11}
    a = displacement_from_relief(OPTICAL_3AXIS, HalfPlaneStep(), pos, **kw)
    b = displacement_from_relief(OPTICAL_3AXIS, HalfPlaneStep(), pos, chunk_poses=5, **kw)
    np.testing.assert_array_equal(a, b)
    c = displacement_from_relief(OPTICAL_3AXIS, HalfPlaneStep(), pos, indent_mm=0.1, rng=12)
    assert not np.array_equal(a, c)


def test_yaw_rotates_the_array_over_the_specimen() -> None:
    u0 = displacement_from_relief(
        OPTICAL_3AXIS, HalfPlaneStep(0.05), [0.0, 0.0], indent_mm=0.1, add_noise=False
    )[0]
    u180 = displacement_from_relief(
        OPTICAL_3AXIS,
        HalfPlaneStep(0.05),
        [0.0, 0.0],
        indent_mm=0.1,
        yaw_deg=180.0,
        add_noise=False,
    )[0]
    np.testing.assert_allclose(u180, u0[::-1, ::-1], atol=1e-6)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"positions_mm": [[0.0, 0.0, 0.0]]}, "positions_mm"),
        ({"positions_mm": [[np.nan, 0.0]]}, "positions_mm"),
        ({"indent_mm": [0.1, 0.2]}, "indent_mm"),
        ({"dtype": np.int32}, "dtype"),
    ],
)
def test_bad_arguments_raise(kwargs: dict[str, Any], match: str) -> None:
    args: dict[str, Any] = {"positions_mm": [[0.0, 0.0]], "indent_mm": 0.1}
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        displacement_from_relief(OPTICAL_3AXIS, HalfPlaneStep(), **args)


def test_vertex_contact_makes_a_point_image_on_the_bonneville_array() -> None:
    """A cube on a vertex touches less than a taxel; the skin dimple makes it visible."""
    from taxelkit.sensors import BONNEVILLE_16X16
    from taxelkit.sensors.press import displacement_from_solid
    from taxelkit.world import Cube, matrix_from_euler_xyz_deg

    rot = matrix_from_euler_xyz_deg([54.7356, 45.0, 0.0])  # body diagonal vertical
    u = displacement_from_solid(
        BONNEVILLE_16X16, Cube(), rot, [0.3, -0.2], indent_mm=0.3, add_noise=False
    )[0]
    contact = BONNEVILLE_16X16.contact_from_displacement(u)
    assert 1 <= contact.sum() <= 6  # a point contact: a few taxels
    i, j = np.unravel_index(np.argmax(u), u.shape)
    centres = BONNEVILLE_16X16.array.centres_mm()
    assert np.hypot(*(centres[i, j] - [0.3, -0.2])) < BONNEVILLE_16X16.array.pitch_mm
    assert u.max() <= 0.3 + 1e-6  # never deeper than the vertex


def test_dimple_does_not_change_a_flat_face_press() -> None:
    from dataclasses import replace

    from taxelkit.sensors import BONNEVILLE_16X16
    from taxelkit.sensors.press import displacement_from_solid
    from taxelkit.world import Cube, Sphere

    off = replace(BONNEVILLE_16X16, skin=replace(BONNEVILLE_16X16.skin, point_dimple=False))
    for body in (Cube(), Sphere()):
        kw: dict[str, Any] = {"indent_mm": 0.3, "add_noise": False, "dtype": np.float64}
        a = displacement_from_solid(BONNEVILLE_16X16, body, np.eye(3), [0.0, 0.0], **kw)
        b = displacement_from_solid(off, body, np.eye(3), [0.0, 0.0], **kw)
        contact_a = BONNEVILLE_16X16.contact_from_displacement(a)
        np.testing.assert_array_equal(contact_a, BONNEVILLE_16X16.contact_from_displacement(b))
