"""plot_course.py: a course's poses drawn (course_plot), read from a bag or a topic (course_plot_ros)."""
