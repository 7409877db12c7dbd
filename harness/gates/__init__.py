"""CI gates: thresholds on summary columns (`gates.toml`), case classes and the verdict table
(`check`)."""
