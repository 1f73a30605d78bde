"""tactile_search: mechanical search by touch, with a GPIS map from vision and touch.

The Rust core (``tactile_search._core``) runs the GPIS, the physics and the episodes; this
package is its Python face.
"""

from tactile_search._core import __version__
from tactile_search.gpis import Gpis

__all__ = ["Gpis", "__version__"]
