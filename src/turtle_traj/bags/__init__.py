"""rosbag2 bags: their types, writing, reading, recording, playing and plotting."""
