"""Make the tools/ package importable and locate the test data."""

import os
import sys

TOOLS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                     "tools")
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
if TOOLS not in sys.path:
    sys.path.insert(0, TOOLS)
