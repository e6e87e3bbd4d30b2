"""Speed and CPU: how fast a course runs, what it costs, how many run at once."""
