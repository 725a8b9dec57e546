"""New objects from their meshes: a row of the tacteme-object table, checked by simulation.

The world-side half of learning: :mod:`taxelkit.world.mesh_features` reads
the geometry; :mod:`~taxelkit.learn.derive` turns it into the tactemes the
object can produce; :mod:`~taxelkit.learn.check` rolls the mesh on the
simulated sensor and compares what the recogniser sees with the row. The
recogniser reads only the resulting table
(:mod:`taxelkit.smart.object_table`).
"""

from taxelkit.learn.derive import derive_row

__all__ = ["derive_row"]
