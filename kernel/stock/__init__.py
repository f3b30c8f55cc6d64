"""Material removal on a height field (Z-map): stock, tool shapes, swept moves and findings.

``heightfield`` holds the grid and the closed-form sweeps of one tool along one line;
``tools`` the tool shapes; ``simulate`` walks a canonical command stream over the stock and
reports the removed volume and the findings (rapid into stock, plunge with a tool that does
not cut at its centre, cut deeper than the flutes); ``mesh`` turns the final height field
into triangles for an STL file. Pure numpy: no file is read or written here.
"""

from kernel.stock.heightfield import HeightField, StockBox, parse_stock
from kernel.stock.simulate import SimFinding, SimResult, simulate_removal
from kernel.stock.tools import ToolShape, library_from_toml, parse_tool_spec, shapes_from_table

__all__ = [
    "HeightField",
    "SimFinding",
    "SimResult",
    "StockBox",
    "ToolShape",
    "library_from_toml",
    "parse_stock",
    "parse_tool_spec",
    "shapes_from_table",
    "simulate_removal",
]
