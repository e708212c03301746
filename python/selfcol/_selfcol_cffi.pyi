# The compiled cffi module (generated from _build_ffi.py).
from typing import Any

ffi: Any
lib: Any
