"""Tests for taxelkit."""
