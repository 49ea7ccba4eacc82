"""blurlab's version, declared once: the package, records and result identities read it."""

__version__ = "0.1.0"
