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
