"""The live view's web server and its messages: plain Python and aiohttp, no ROS."""
