"""Probe: one cloud of publish_pointcloud2.py's /points2, summarised as JSON (a rospy script)."""

import json

import rospy
from sensor_msgs import point_cloud2
from sensor_msgs.msg import PointCloud2

rospy.init_node("points_probe", anonymous=True)
msg = rospy.wait_for_message("/points2", PointCloud2)
points = list(point_cloud2.read_points(msg))
print(json.dumps({
    "frame_id": msg.header.frame_id, "height": msg.height, "width": msg.width,
    "fields": [[f.name, f.offset, f.datatype, f.count] for f in msg.fields],
    "is_bigendian": msg.is_bigendian, "point_step": msg.point_step, "row_step": msg.row_step,
    "is_dense": msg.is_dense, "bytes": len(msg.data), "points": len(points),
    "first": [[round(v, 4) for v in p[:2]] for p in points[:3]],
    "z_within": all(abs(p[2]) <= 0.5 and p[3] == p[2] for p in points),
}, sort_keys=True))
