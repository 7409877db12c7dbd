"""The HTML report of a results folder: `page.build_report` draws the headline, the verdicts,
one section per case and the extra sections of `sections.REPORT_SECTIONS` (interference,
shifter, mitigation, and whatever a plugin registers); `figures` holds the building blocks."""
