"""Independent peer readers (pygcode, cncjs's gcode-toolpath) run on our writers' output."""
