"""What is to be solved: targets, loops, loads and priorities, the problem and its variables, scenarios."""
