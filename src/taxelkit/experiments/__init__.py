"""Registered experiments: each returns a frozen result object."""
