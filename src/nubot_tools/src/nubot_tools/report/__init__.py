"""A match's report from its bag alone (``match_report``) and its plots (``match_plots``)."""
