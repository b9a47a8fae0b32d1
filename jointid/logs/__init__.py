"""Source 2, a recorded log: a file in, samples ready to fit out.

- `request`: which log to load and how (file, joint, time window, torque scale);
- `csv_reader`, `bag`: read a CSV file or a ROS bag's joint into a `table`;
- `table`: the columns as read, and the errors every reader raises;
- `pipeline`: every table is checked, timed, differentiated and converted here;
- `timing`, `timewindow`, `derivatives`: the time checks and resampling, time windows, Savitzky-Golay derivatives.
"""
