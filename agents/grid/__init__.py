"""The grid of training trials and their evaluation: one trial (``trials``), the pipeline's
budgets and steps (``pipeline``), and the Ray scheduler (``ray_scheduler``, on the Ray
session of ``ray_session``); without Ray the pipeline runs the same trials in this process."""
