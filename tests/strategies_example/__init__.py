"""A tiny importable package of strategies, for the ``allocator = "package.module:Class"`` tests."""
