"""Make the tools/ package (and hrbench_analysis.engine, which it uses) importable and
locate the test data."""

import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = os.path.join(ROOT, "tools")
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
for path in (os.path.join(ROOT, "analysis"), TOOLS):
    if path not in sys.path:
        sys.path.insert(0, path)
