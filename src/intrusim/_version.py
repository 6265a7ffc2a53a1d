"""The package version (a leaf module: any module may import it; ``intrusim`` re-exports it)."""

__version__ = "0.1.0"
