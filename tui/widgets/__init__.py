"""The explorer's widgets.

One convention throughout: a widget shows what its owner gives it (a `show...`
method) and reports the user's choices through a callback passed at
construction, called inside the key's own handler. A Textual message would be
handled a turn of the event loop later, with a paint in between: about 50 ms
for one key where a frame is 16.7 ms (see direct_controls.py).
"""
