"""Controller models: planner strategies that reproduce a real control's trajectory planner
(``[controller] model`` in the machine profile; kernel.plan.strategy picks one)."""
