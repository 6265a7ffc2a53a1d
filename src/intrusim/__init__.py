"""intrusim: granular intrusion with MPM, RFT and Dynamic RFT.

Reproduces Agarwal, Karsai, Goldman & Kamrin (2021), "Surprising simplicity in the
modeling of dynamic granular intrusion", Science Advances. SI units throughout.
"""

__version__ = "0.1.0"
