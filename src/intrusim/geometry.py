"""2D intruder shapes and their surface elements.

An intruder lives in its BODY frame: x forward, z up, lengths in metres, the body's
reference point (wheel axle, plate centre) at the origin. A :class:`Shape` carries

* ``polygon``: the closed outline (counter-clockwise vertices), used by the MPM solver;
* ``elements``: the surface elements used by RFT/DRFT (midpoint, outward unit normal,
  length), plus the out-of-plane ``width`` that turns a length into an area dA.

Builders: :func:`grousered_wheel` and :func:`four_flap_runner` (a hub with rectangular
lugs, Table S1), :func:`circle`, :func:`plate` (a thin flat plate at any angle) and
:func:`polygon_shape` (any simple closed polygon).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from intrusim._checks import InputError, finite, finite_array, positive, positive_int

# Element tags: which part of the surface an element belongs to.
TAG_SURFACE = 0  # rim / hub / plain polygon edge / plate face
TAG_LUG_SIDE = 1  # side face of a grouser or flap
TAG_LUG_TIP = 2  # outer face of a grouser or flap


@dataclass(frozen=True)
class SurfaceElements:
    """Surface elements of a 2D body, in the body frame.

    Attributes
    ----------
    midpoint : (N, 2) array, m
    normal : (N, 2) array, outward unit normals
    length : (N,) array, m (in-plane extent of each element)
    width : float, m (out-of-plane extent; area dA = length * width)
    tag : (N,) int array, one of TAG_SURFACE, TAG_LUG_SIDE, TAG_LUG_TIP
    """

    midpoint: np.ndarray
    normal: np.ndarray
    length: np.ndarray
    width: float
    tag: np.ndarray = field(default=None)  # type: ignore[assignment]

    def __post_init__(self) -> None:
        mid = finite_array("midpoint", self.midpoint, (2,)).reshape(-1, 2)
        nor = finite_array("normal", self.normal, (2,)).reshape(-1, 2)
        ln = finite_array("length", self.length).reshape(-1)
        if len(mid) == 0:
            raise InputError("a body needs at least one surface element (got zero)")
        if not (len(mid) == len(nor) == len(ln)):
            raise InputError("midpoint, normal and length must have the same number of elements")
        if np.any(ln <= 0):
            raise InputError("every element length must be > 0")
        norm = np.linalg.norm(nor, axis=1)
        if np.any(np.abs(norm - 1.0) > 1e-9):
            raise InputError("normals must be unit vectors")
        tag = np.zeros(len(mid), dtype=np.int8) if self.tag is None else np.asarray(self.tag, np.int8)
        if tag.shape != (len(mid),):
            raise InputError("tag must have one entry per element")
        object.__setattr__(self, "midpoint", mid)
        object.__setattr__(self, "normal", nor)
        object.__setattr__(self, "length", ln)
        object.__setattr__(self, "width", positive("width", self.width))
        object.__setattr__(self, "tag", tag)

    def __len__(self) -> int:
        return len(self.length)

    @property
    def area(self) -> np.ndarray:
        """Element areas dA = length * width, m^2."""
        return self.length * self.width

    def mirrored(self) -> "SurfaceElements":
        """The same elements mirrored x -> -x (a left-right flip of the body)."""
        flip = np.array([-1.0, 1.0])
        return SurfaceElements(self.midpoint * flip, self.normal * flip, self.length, self.width, self.tag)

    @staticmethod
    def concatenate(parts: list["SurfaceElements"]) -> "SurfaceElements":
        """Join element sets of the same width."""
        widths = {p.width for p in parts}
        if len(widths) != 1:
            raise InputError("cannot join element sets of different widths")
        return SurfaceElements(
            np.concatenate([p.midpoint for p in parts]),
            np.concatenate([p.normal for p in parts]),
            np.concatenate([p.length for p in parts]),
            parts[0].width,
            np.concatenate([p.tag for p in parts]),
        )


@dataclass(frozen=True)
class Shape:
    """A rigid 2D intruder: outline polygon, RFT surface elements and nominal size.

    Attributes
    ----------
    name : str
    polygon : (M, 2) array, counter-clockwise outline in the body frame, m
    elements : SurfaceElements
    radius : float, m. Nominal radius (outer radius of a wheel, half-length of a plate),
        the r of slip = 1 - v / (r omega) and of the structural correction dh = r psi(r omega^2/g).
    symmetry : int. Order of the rotational symmetry (the shape repeats every 2 pi / symmetry: the
        lug count of a hub with lugs, the segment count of a polygonal circle; 1 for none). A turning
        body's force repeats at that period, which the locomotion time step is chosen against
        (:meth:`intrusim.scenarios.RunConfig.dt`).
    """

    name: str
    polygon: np.ndarray
    elements: SurfaceElements
    radius: float
    symmetry: int = 1

    @property
    def width(self) -> float:
        return self.elements.width

    @property
    def outer_diameter(self) -> float:
        """Largest distance of the outline from the reference point, times two (m)."""
        return 2.0 * float(np.max(np.linalg.norm(self.polygon, axis=1)))


# ---------------------------------------------------------------------------------------
# Segments and arcs -> elements
# ---------------------------------------------------------------------------------------


def _segment_elements(p0: np.ndarray, p1: np.ndarray, n: int, tag: int, width: float) -> SurfaceElements:
    """Split the straight segment p0 -> p1 into n elements; outward normal on its right.

    For a counter-clockwise outline the outside lies to the right of the travel direction,
    so the outward normal of direction (dx, dz) is (dz, -dx) / length.
    """
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    d = p1 - p0
    seg_len = float(np.hypot(*d))
    t = (np.arange(n) + 0.5) / n
    mid = p0 + t[:, None] * d
    nrm = np.tile(np.array([d[1], -d[0]]) / seg_len, (n, 1))
    return SurfaceElements(mid, nrm, np.full(n, seg_len / n), width, np.full(n, tag))


def _arc_elements(radius: float, a0: float, a1: float, n: int, width: float) -> SurfaceElements:
    """Split the circular arc of ``radius`` from angle a0 to a1 (a1 > a0) into n elements.

    Midpoints lie on the arc, normals are radial, lengths are exact arc lengths.
    """
    edges = np.linspace(a0, a1, n + 1)
    mids = 0.5 * (edges[:-1] + edges[1:])
    nrm = np.column_stack([np.cos(mids), np.sin(mids)])
    return SurfaceElements(radius * nrm, nrm, np.full(n, radius * (a1 - a0) / n), width, np.zeros(n, np.int8))


# ---------------------------------------------------------------------------------------
# Hub with rectangular lugs: grousered wheel and four-flap runner
# ---------------------------------------------------------------------------------------


def hub_with_lugs(
    hub_radius: float,
    lug_height: float,
    lug_width: float,
    lug_count: int,
    width: float,
    *,
    hub_elements_per_segment: int = 14,
    lug_elements_per_face: int = 8,
    lug_height_scale: float = 1.0,
    name: str = "hub_with_lugs",
) -> Shape:
    """A circular hub with ``lug_count`` rectangular lugs, evenly spaced (see :func:`_hub_with_lugs`).

    Building the outline and ~800 elements costs a few ms, more than a whole compiled steady-state
    run, so shapes are memoised on their arguments. Every call returns a fresh Shape with its own
    arrays (copies of the cached ones), so a caller may modify what it gets.
    """
    args = (hub_radius, lug_height, lug_width, lug_count, width)
    kwargs = dict(hub_elements_per_segment=hub_elements_per_segment, lug_elements_per_face=lug_elements_per_face,
                  lug_height_scale=lug_height_scale, name=name)  # fmt: skip
    try:
        hit = _cached_hub_with_lugs(*args, **kwargs)
    except TypeError:  # unhashable argument: build without the cache (validation reports it)
        hit = _hub_with_lugs(*args, **kwargs)
    e = hit.elements
    return Shape(
        hit.name,
        hit.polygon.copy(),
        SurfaceElements(e.midpoint.copy(), e.normal.copy(), e.length.copy(), e.width, e.tag.copy()),
        hit.radius,
        hit.symmetry,
    )


def _hub_with_lugs(
    hub_radius: float,
    lug_height: float,
    lug_width: float,
    lug_count: int,
    width: float,
    *,
    hub_elements_per_segment: int = 14,
    lug_elements_per_face: int = 8,
    lug_height_scale: float = 1.0,
    name: str = "hub_with_lugs",
) -> Shape:
    """A circular hub with ``lug_count`` rectangular lugs, evenly spaced.

    Lug k is centred on the body-frame angle 2 pi k / N (lug 0 points along +x). Its two
    side faces are parallel to its centre line, at +-lug_width/2, from the hub surface to
    the flat tip at radial distance hub_radius + lug_height.

    Parameters
    ----------
    hub_radius, lug_height, lug_width, width : float, m
    lug_count : int, >= 1
    hub_elements_per_segment : int
        Elements on each hub arc between two lugs (the paper: 14).
    lug_elements_per_face : int
        Elements on each lug face: tip and two sides (the paper: 8).
    lug_height_scale : float in (0, 1]
        Scales the lug height of the ELEMENTS only (RFT grouser shadowing: the paper uses 1/3);
        the outline polygon keeps the true height.
    """
    r = positive("hub_radius", hub_radius)
    h = positive("lug_height", lug_height)
    w = positive("lug_width", lug_width)
    n_lugs = positive_int("lug_count", lug_count)
    width = positive("width", width)
    n_hub = positive_int("hub_elements_per_segment", hub_elements_per_segment)
    n_lug = positive_int("lug_elements_per_face", lug_elements_per_face)
    scale = positive("lug_height_scale", lug_height_scale)
    if scale > 1.0:
        raise InputError(f"lug_height_scale must be <= 1, got {lug_height_scale!r}")
    if w >= 2 * r:
        raise InputError(f"lug_width ({w}) must be smaller than the hub diameter ({2 * r})")
    half = np.arcsin(0.5 * w / r)  # half-angle of a lug's footprint on the hub
    pitch = 2 * np.pi / n_lugs
    if 2 * half >= pitch:
        raise InputError(f"{n_lugs} lugs of width {w} m do not fit on a hub of radius {r} m (they overlap)")
    base = np.sqrt(r * r - 0.25 * w * w)  # radial coordinate where a lug side meets the hub

    def lug_frame(phi: float) -> tuple[np.ndarray, np.ndarray]:
        return np.array([np.cos(phi), np.sin(phi)]), np.array([-np.sin(phi), np.cos(phi)])

    parts: list[SurfaceElements] = []
    outline: list[np.ndarray] = []
    for k in range(n_lugs):
        phi = k * pitch
        er, et = lug_frame(phi)

        def corners(tip: float) -> list[np.ndarray]:
            return [
                base * er - 0.5 * w * et,
                tip * er - 0.5 * w * et,
                tip * er + 0.5 * w * et,
                base * er + 0.5 * w * et,
            ]

        c = corners(r + h * scale)  # elements: possibly shadowed height
        parts.append(_segment_elements(c[0], c[1], n_lug, TAG_LUG_SIDE, width))
        parts.append(_segment_elements(c[1], c[2], n_lug, TAG_LUG_TIP, width))
        parts.append(_segment_elements(c[2], c[3], n_lug, TAG_LUG_SIDE, width))
        outline.extend(corners(r + h))  # outline: true height
        a0, a1 = phi + half, phi + pitch - half
        parts.append(_arc_elements(r, a0, a1, n_hub, width))
        arc = np.linspace(a0, a1, max(n_hub, 2) + 1)[1:-1]
        outline.extend(r * np.column_stack([np.cos(arc), np.sin(arc)]))
    return Shape(name, np.array(outline), SurfaceElements.concatenate(parts), r + h, n_lugs)


_cached_hub_with_lugs = functools.lru_cache(maxsize=64, typed=True)(_hub_with_lugs)


def grousered_wheel(
    inner_diameter: float = 0.188,
    grouser_height: float = 0.012,
    grouser_width: float = 0.006,
    grouser_count: int = 20,
    width: float = 0.140,
    *,
    rim_elements_per_segment: int = 14,
    lug_elements_per_face: int = 8,
    grouser_height_scale: float = 1.0,
) -> Shape:
    """The grousered wheel of Table S1 (defaults): inner circle plus rectangular grousers.

    The paper's discretisation (14 elements per rim segment, 8 per grouser face) gives
    N (14 + 3 * 8) = 38 N elements: 760 for the 20-grouser wheel of Table S1. The paper quotes
    570 elements, which is 38 x 15; see docs/rft.md.
    """
    d = positive("inner_diameter", inner_diameter)
    return hub_with_lugs(
        0.5 * d,
        grouser_height,
        grouser_width,
        grouser_count,
        width,
        hub_elements_per_segment=rim_elements_per_segment,
        lug_elements_per_face=lug_elements_per_face,
        lug_height_scale=grouser_height_scale,
        name="grousered_wheel",
    )


def four_flap_runner(
    inner_diameter: float = 0.050,
    flap_length: float = 0.070,
    flap_width: float = 0.014,
    flap_count: int = 4,
    width: float = 1.0,
    *,
    hub_elements_per_segment: int = 14,
    flap_elements_per_face: int = 16,
) -> Shape:
    """The four-flap runner of Table S1 (defaults): a 50 mm hub with four 70 x 14 mm flaps."""
    d = positive("inner_diameter", inner_diameter)
    return hub_with_lugs(
        0.5 * d,
        flap_length,
        flap_width,
        flap_count,
        width,
        hub_elements_per_segment=hub_elements_per_segment,
        lug_elements_per_face=flap_elements_per_face,
        name="four_flap_runner",
    )


def circle(radius: float, width: float, n_elements: int = 360) -> Shape:
    """A round body (no lugs) discretised into ``n_elements`` arc elements."""
    r = positive("radius", radius)
    n = positive_int("n_elements", n_elements)
    els = _arc_elements(r, 0.0, 2 * np.pi, n, positive("width", width))
    a = np.linspace(0, 2 * np.pi, max(n, 16), endpoint=False)
    return Shape("circle", r * np.column_stack([np.cos(a), np.sin(a)]), els, r)


# ---------------------------------------------------------------------------------------
# Plate and arbitrary polygon
# ---------------------------------------------------------------------------------------


def plate(
    length: float,
    width: float,
    angle: float = 0.0,
    *,
    n_elements: int = 20,
    thickness: float = 1e-3,
) -> Shape:
    """A thin flat plate centred on the origin, tilted by ``angle`` (rad, counter-clockwise from +x).

    RFT sees a thin plate: two faces of ``n_elements`` each, with opposite normals and the
    same midpoints (the leading-edge rule picks the face moving into the medium). The outline
    polygon (for MPM) is a rectangle of the given ``thickness``.
    """
    L = positive("length", length)
    a = finite("angle", angle)
    n = positive_int("n_elements", n_elements)
    t = positive("thickness", thickness)
    width = positive("width", width)
    tan = np.array([np.cos(a), np.sin(a)])
    nrm = np.array([-np.sin(a), np.cos(a)])
    p0, p1 = -0.5 * L * tan, 0.5 * L * tan
    top = _segment_elements(p1, p0, n, TAG_SURFACE, width)  # right of p1->p0 is +nrm
    bottom = _segment_elements(p0, p1, n, TAG_SURFACE, width)
    outline = np.array([p0 - 0.5 * t * nrm, p1 - 0.5 * t * nrm, p1 + 0.5 * t * nrm, p0 + 0.5 * t * nrm])
    return Shape("plate", outline, SurfaceElements.concatenate([top, bottom]), 0.5 * L)


def posed_polygon(polygon: np.ndarray, x: float, z: float, theta: float) -> np.ndarray:
    """A body-frame polygon (N, 2) turned by theta (counter-clockwise) and moved to (x, z), m."""
    c, s = np.cos(theta), np.sin(theta)
    return np.asarray(polygon, float) @ np.array([[c, s], [-s, c]]) + np.array([x, z])


def signed_area(points: np.ndarray) -> float:
    """Shoelace area of a closed polygon: > 0 for counter-clockwise vertices (m^2)."""
    x, z = points[:, 0], points[:, 1]
    return 0.5 * float(np.sum(x * np.roll(z, -1) - np.roll(x, -1) * z))


def self_intersections(points: np.ndarray) -> list[tuple[int, int]]:
    """Pairs (i, j) of non-adjacent edges of the closed polygon that intersect.

    Edge i joins vertex i to vertex i+1 (cyclically). Vectorised orientation tests.
    """
    p = np.asarray(points, float)
    n = len(p)
    a, b = p, np.roll(p, -1, axis=0)

    def orient(p1: np.ndarray, p2: np.ndarray, p3: np.ndarray) -> np.ndarray:
        return (p2[..., 0] - p1[..., 0]) * (p3[..., 1] - p1[..., 1]) - (p2[..., 1] - p1[..., 1]) * (
            p3[..., 0] - p1[..., 0]
        )

    i, j = np.triu_indices(n, k=2)
    keep = ~((i == 0) & (j == n - 1))  # first and last edges share a vertex
    i, j = i[keep], j[keep]
    o1 = orient(a[i], b[i], a[j])
    o2 = orient(a[i], b[i], b[j])
    o3 = orient(a[j], b[j], a[i])
    o4 = orient(a[j], b[j], b[i])
    hit = (o1 * o2 < 0) & (o3 * o4 < 0)
    return list(zip(i[hit].tolist(), j[hit].tolist()))


def polygon_shape(
    points: np.ndarray | list,
    width: float,
    *,
    element_size: float | None = None,
    name: str = "polygon",
) -> Shape:
    """Any simple closed polygon (list of (x, z) vertices in the body frame, m).

    Vertices may be given clockwise or counter-clockwise (they are stored counter-clockwise).
    Each edge is split into ceil(edge_length / element_size) elements; the default element
    size is 1/100 of the perimeter.
    """
    p = finite_array("points", points, (2,))
    if p.ndim != 2 or len(p) < 3:
        raise InputError(f"a polygon needs at least 3 vertices, got {len(p) if p.ndim == 2 else p.shape}")
    edges = np.roll(p, -1, axis=0) - p
    edge_len = np.hypot(edges[:, 0], edges[:, 1])
    if np.any(edge_len <= 0):
        raise InputError("polygon has repeated consecutive vertices (zero-length edge)")
    hits = self_intersections(p)
    if hits:
        raise InputError(f"polygon is self-intersecting: edges {hits[0][0]} and {hits[0][1]} cross")
    area = signed_area(p)
    if abs(area) <= 1e-12 * max(edge_len.max() ** 2, 1e-300):
        raise InputError("polygon has zero area")
    if area < 0:
        p = p[::-1].copy()
        edge_len = np.hypot(*(np.roll(p, -1, axis=0) - p).T)
    size = float(edge_len.sum()) / 100 if element_size is None else positive("element_size", element_size)
    width = positive("width", width)
    parts = [
        _segment_elements(
            p[k], p[(k + 1) % len(p)], max(1, int(np.ceil(edge_len[k] / size - 1e-9))), TAG_SURFACE, width
        )
        for k in range(len(p))
    ]
    centroid_dist = float(np.max(np.linalg.norm(p, axis=1)))
    return Shape(name, p, SurfaceElements.concatenate(parts), centroid_dist)


def element_count_for_wheel(grouser_count: int, rim_per_segment: int = 14, lug_per_face: int = 8) -> int:
    """Number of RFT elements of a grousered wheel: N (rim + 3 lug faces)."""
    return grouser_count * (rim_per_segment + 3 * lug_per_face)


__all__ = [
    "TAG_SURFACE",
    "TAG_LUG_SIDE",
    "TAG_LUG_TIP",
    "SurfaceElements",
    "Shape",
    "hub_with_lugs",
    "grousered_wheel",
    "four_flap_runner",
    "circle",
    "plate",
    "polygon_shape",
    "signed_area",
    "self_intersections",
    "element_count_for_wheel",
]
