"""Stable names of what usdksl warns about or leaves unchecked, as OpenUSD names its validators
(``<plugin>:<Name>``). Reports (JSON, the coverage account) carry them so that a pipeline can filter or
accept findings by kind without parsing message text; the names never change once released.
"""

#: A vertex moves far beyond its mesh's motion between two samples (usdksl.reading.blowups).
BLOW_UP = "usdksl:BlowUp"
#: A whole mesh, or a connected part of it, jumps away and back between samples (a cache glitch).
CACHE_GLITCH = "usdksl:CacheGlitch"
#: A composed asset (reference, payload, sublayer, value clip) does not resolve.
UNRESOLVED_ASSET = "usdksl:UnresolvedAsset"
#: A points sample is empty or value-blocked: the mesh is not checked across it.
EMPTY_SAMPLE = "usdksl:EmptySample"
#: A mesh's topology changes between two samples: the interval across the change is not checked for it.
TOPOLOGY_CHANGE = "usdksl:TopologyChange"
#: A mesh has samples outside the requested --time-range; they are not checked.
OUTSIDE_TIME_RANGE = "usdksl:OutsideTimeRange"
#: A mesh is left out by a scoping rule (--prims/--exclude, physics:collisionEnabled, purpose, visibility).
SCOPED_OUT = "usdksl:ScopedOut"
#: A solid gprim that is not a UsdGeom.Mesh (Cube, Sphere, NurbsPatch...): usdksl checks meshes only.
UNMESHED_SOLID = "usdksl:UnmeshedSolid"
#: Curves, points or a volume: geometry, but not a surface a contact is defined on (scoped out, no warning).
NOT_A_SURFACE = "usdksl:NotASurface"
#: A PointInstancer inside a prototype: its instances are not expanded.
NESTED_INSTANCER = "usdksl:NestedInstancer"
#: A mesh with no points, no faces or only degenerate faces at every sample.
EMPTY_MESH = "usdksl:EmptyMesh"
#: A skinned mesh keyed more sparsely than the stage's frames is posed at every frame (as BakeSkinning).
SPARSE_SKIN_KEYS = "usdksl:SparseSkinKeys"
#: No mesh pair is left to check, or the requested time range holds no sample.
NOTHING_CHECKED = "usdksl:NothingChecked"
#: More than half of the prims a baseline names are not meshes of the shot: made from another shot?
BASELINE_MISMATCH = "usdksl:BaselineMismatch"
