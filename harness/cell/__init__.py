"""One sweep cell: what it runs (`spec`), the radar and processing configs it builds (`config`,
`ti_profile` for TI profiles), its parts (`components`) and the frame loop that simulates,
processes, tracks and scores it (`run`)."""
