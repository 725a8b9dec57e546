"""Manipulator motion: point-to-point moves and scans."""
