"""Source 2, a recorded log: a file in, samples ready to fit out.

- `request`: which log to load and how (file, joint, time window, torque scale);
- `csv_reader`, `bag`, `arrays`: read a CSV file, a ROS bag's joint or arrays in memory into a `table`;
- `conventions`, `angles`: column names and maps, where the angle's 0 points and which way it grows, wrapped
  and far-off angles;
- `table`: the columns as read, and the errors every reader raises;
- `pipeline`: every table is checked, timed, differentiated and converted here;
- `timing`, `timewindow`, `derivatives`: the time checks and resampling, time windows, Savitzky-Golay derivatives.
"""
