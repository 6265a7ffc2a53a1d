"""MP4 movies of simulation fields via imageio-ffmpeg (Movies S7, S8)."""

from __future__ import annotations

from pathlib import Path
from typing import Callable, Iterable

import numpy as np


def figure_to_rgb(fig) -> np.ndarray:
    """Render a matplotlib figure to an (H, W, 3) uint8 array (even dimensions for H.264)."""
    fig.canvas.draw()
    rgb = np.asarray(fig.canvas.buffer_rgba())[..., :3]
    h, w = rgb.shape[0] // 2 * 2, rgb.shape[1] // 2 * 2
    return np.ascontiguousarray(rgb[:h, :w])


def write_movie(frames: Iterable[np.ndarray], path: str | Path, fps: float = 20.0) -> Path:
    """Write RGB frames (H, W, 3 uint8, all the same size) to an H.264 MP4 file.

    The file is written to a temporary name and renamed when complete, so a failure never
    leaves a truncated movie behind.
    """
    import imageio_ffmpeg

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".part.mp4")
    writer = None
    count = 0
    try:
        for frame in frames:
            frame = np.ascontiguousarray(frame, dtype=np.uint8)
            if writer is None:
                h, w = frame.shape[:2]
                writer = imageio_ffmpeg.write_frames(
                    str(tmp), (w, h), fps=fps, codec="libx264", pix_fmt_out="yuv420p", macro_block_size=2
                )
                writer.send(None)
            writer.send(frame)
            count += 1
    finally:
        if writer is not None:
            writer.close()
    if count == 0:
        raise ValueError("write_movie got no frames")
    tmp.replace(path)
    return path


def render_frames(draw: Callable[[int], np.ndarray], n: int) -> Iterable[np.ndarray]:
    """Lazily call ``draw(i)`` for i in range(n) (frames are not all kept in memory)."""
    for i in range(n):
        yield draw(i)


def movie_from_frames(
    frames_dir: str | Path,
    path: str | Path,
    field: str = "gdot_p",
    fps: float = 20.0,
    crop: tuple[float, float, float, float] | None = None,
    vmin: float = 0.1,
    vmax: float = 100.0,
) -> Path:
    """Render the ``frame_*.npz`` files of an MPM run (see MPMSettings.frames_every) to MP4.

    Particles are coloured by ``field`` ("gdot_p": plastic strain rate 1/s, log scale;
    "speed": m/s; "eps_p": equivalent plastic strain), the body outline is drawn in black.
    ``crop`` = (x0, x1, z0, z1) in m; default: the whole extent of the particles.
    """
    import matplotlib

    from intrusim.geometry import posed_polygon

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm, Normalize

    files = sorted(Path(frames_dir).glob("frame_*.npz"))
    if not files:
        raise FileNotFoundError(f"no frame_*.npz files in {frames_dir}: run with frames_every set")
    first = np.load(files[0])
    if field not in first:
        raise ValueError(f"field must be one of gdot_p, speed, eps_p; got {field!r}")
    if crop is None:
        x = first["x"]
        crop = (float(x[:, 0].min()), float(x[:, 0].max()), float(x[:, 1].min()), float(x[:, 1].max()) + 0.15)
    norm = LogNorm(vmin, vmax) if field == "gdot_p" else Normalize(vmin, vmax)
    label = {"gdot_p": "plastic strain rate (1/s)", "speed": "speed (m/s)", "eps_p": "plastic strain"}[field]
    aspect = (crop[3] - crop[2]) / (crop[1] - crop[0])
    fig, ax = plt.subplots(figsize=(8, max(2.5, 8 * aspect) + 0.6), dpi=100)
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=ax, label=label, fraction=0.03)
    # marker diameter = particle spacing (from the initial bed's area per particle), in points
    x0 = first["x"]
    spacing = np.sqrt(np.ptp(x0[:, 0]) * np.ptp(x0[:, 1]) / len(x0))
    axes_width_in = fig.get_size_inches()[0] * 0.8
    marker = (1.1 * spacing / (crop[1] - crop[0]) * axes_width_in * 72.0) ** 2

    def draw(i: int) -> np.ndarray:
        d = np.load(files[i])
        ax.clear()
        vals = np.clip(d[field], vmin if field == "gdot_p" else -np.inf, None)
        ax.scatter(d["x"][:, 0], d["x"][:, 1], c=vals, s=marker, cmap="viridis", norm=norm, linewidths=0)
        poly = posed_polygon(d["outline"], *d["body"][:3])
        ax.fill(poly[:, 0], poly[:, 1], color="0.6", ec="k", lw=0.8)
        ax.set_xlim(crop[0], crop[1])
        ax.set_ylim(crop[2], crop[3])
        ax.set_aspect("equal")
        ax.set_title(f"t = {float(d['t']):.2f} s")
        return figure_to_rgb(fig)

    try:
        return write_movie(render_frames(draw, len(files)), path, fps)
    finally:
        plt.close(fig)
