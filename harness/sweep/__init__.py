"""Sweeps: the sweep value (`spec`), its TOML file (`file`), scheduling and resume on a process
pool (`schedule`) or a Dask cluster (`dask_cluster`), one cell in a worker (`worker`), the
resumable cell store (`store`), random streams (`streams`), provenance of a results folder
(`provenance`) and the result tables assembled from the cells (`assemble`)."""
