"""Contact regions: the check's contacting face pairs grouped into the problems a person fixes, and how deep
each goes (docs/contracts.md, Regions).

:mod:`.table` holds the model (RegionTable, DepthSamples); :mod:`.closed` says which meshes are closed
(watertight), :mod:`.grouping` groups contact rows into regions and :mod:`.depth` measures each region at the
whole-frame samples of its span, both in the native core (``usdksl._native``; these modules only hand it arrays);
:mod:`.find` folds the two into a RegionTable, :mod:`.csv_file` writes it as regions.csv and :mod:`.baseline`
holds a check against regions accepted earlier.
"""
