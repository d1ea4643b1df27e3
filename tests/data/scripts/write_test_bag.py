#!/usr/bin/python3
"""Writes an EuRoC ASL folder (e.g. from `adugs sim`) as a ROS1 bag with Debian's python3-rosbag,
in the topic layout of a public dataset, for the playback tests.

  write_test_bag.py ASL_ROOT OUT.bag --layout viode|openloris|euroc [--compression none|bz2|lz4]
                    [--kalibr-out DIR] [--seed N]

Layouts (what the real recorders write):
  viode      /cam0/image_raw bgr8, /imu0 (sensor_msgs/Imu), /odometry (nav_msgs/Odometry)
  euroc      /cam0/image_raw mono8, /imu0
  openloris  /d400/color/image_raw rgb8, /d400/accel/sample at 250 Hz and /d400/gyro/sample at
             400 Hz (two sensor_msgs/Imu topics; the ASL IMU must be at 400 Hz: the gyro keeps its
             samples, the accelerometer is resampled at 250 Hz by linear interpolation)
Record times are the stamps plus a random delay (images 5-30 ms, IMU 0-3 ms), so the bag is out
of header.stamp order as real recordings are. --kalibr-out also writes the sequence's calibration
as Kalibr camchain-imucam.yaml and imu.yaml (T_cam_imu = T_BS^-1).
"""
import argparse
import csv
import os
import random
import sys

import numpy as np
import rosbag
import rospy
import yaml
from geometry_msgs.msg import Quaternion, Vector3
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image, Imu

import cv2  # noqa: E402  (python3-opencv)


def rows(path):
    with open(path) as f:
        return [r for r in csv.reader(f) if r and not r[0].startswith('#')]


def stamp(t_ns):
    return rospy.Time(secs=t_ns // 1000000000, nsecs=t_ns % 1000000000)


def imu_msg(t_ns, gyro, accel):
    m = Imu()
    m.header.stamp = stamp(t_ns)
    m.header.frame_id = 'imu'
    m.angular_velocity = Vector3(*gyro)
    m.linear_acceleration = Vector3(*accel)
    m.orientation_covariance[0] = -1.0  # no orientation, as IMU drivers publish
    return m


def image_msg(t_ns, grey, encoding):
    m = Image()
    m.header.stamp = stamp(t_ns)
    m.header.frame_id = 'cam0'
    m.height, m.width = grey.shape
    if encoding == 'mono8':
        data = grey
    else:
        data = np.dstack([grey, grey, grey])  # a grey picture: every channel order converts back exactly
    m.encoding = encoding
    m.is_bigendian = 0
    m.step = m.width * (1 if encoding == 'mono8' else 3)
    m.data = np.ascontiguousarray(data).tobytes()
    return m


def write_kalibr(asl, out_dir):
    mav = os.path.join(asl, 'mav0')
    text = open(os.path.join(mav, 'cam0', 'sensor.yaml')).read().replace('%YAML:1.0', '')
    cam = yaml.safe_load(text)
    T_BS = np.array(cam['T_BS']['data'], dtype=float).reshape(4, 4)
    T_cam_imu = np.linalg.inv(T_BS)
    imu = yaml.safe_load(open(os.path.join(mav, 'imu0', 'sensor.yaml')).read().replace('%YAML:1.0', ''))
    os.makedirs(out_dir, exist_ok=True)
    dist = {'radial-tangential': 'radtan', 'equidistant': 'equidistant'}[cam['distortion_model']]
    with open(os.path.join(out_dir, 'camchain-imucam.yaml'), 'w') as f:
        f.write('cam0:\n  camera_model: pinhole\n')
        f.write('  intrinsics: [%s]\n' % ', '.join(repr(float(v)) for v in cam['intrinsics']))
        f.write('  distortion_model: %s\n' % dist)
        f.write('  distortion_coeffs: [%s]\n' % ', '.join(repr(float(v)) for v in cam['distortion_coefficients']))
        f.write('  resolution: [%d, %d]\n' % tuple(cam['resolution']))
        f.write('  T_cam_imu:\n')
        for r in T_cam_imu:
            f.write('  - [%s]\n' % ', '.join(repr(float(v)) for v in r))
        f.write('  timeshift_cam_imu: 0.0\n  rostopic: /cam0/image_raw\n')
    with open(os.path.join(out_dir, 'imu.yaml'), 'w') as f:
        f.write('imu0:\n')
        f.write('  accelerometer_noise_density: %r\n' % float(imu['accelerometer_noise_density']))
        f.write('  accelerometer_random_walk: %r\n' % float(imu['accelerometer_random_walk']))
        f.write('  gyroscope_noise_density: %r\n' % float(imu['gyroscope_noise_density']))
        f.write('  gyroscope_random_walk: %r\n' % float(imu['gyroscope_random_walk']))
        f.write('  update_rate: %r\n  rostopic: /imu0\n' % float(imu['rate_hz']))


def main():
    p = argparse.ArgumentParser()
    p.add_argument('asl')
    p.add_argument('bag')
    p.add_argument('--layout', choices=['viode', 'openloris', 'euroc'], required=True)
    p.add_argument('--compression', choices=['none', 'bz2', 'lz4'], default='none')
    p.add_argument('--kalibr-out')
    p.add_argument('--seed', type=int, default=1)
    a = p.parse_args()
    rnd = random.Random(a.seed)
    mav = os.path.join(a.asl, 'mav0')
    if a.kalibr_out:
        write_kalibr(a.asl, a.kalibr_out)

    image_topic = '/d400/color/image_raw' if a.layout == 'openloris' else '/cam0/image_raw'
    encoding = {'viode': 'bgr8', 'openloris': 'rgb8', 'euroc': 'mono8'}[a.layout]
    records = []  # (record time ns, topic, message)

    for t, name in rows(os.path.join(mav, 'cam0', 'data.csv')):
        t = int(t)
        grey = cv2.imread(os.path.join(mav, 'cam0', 'data', name), cv2.IMREAD_GRAYSCALE)
        records.append((t + rnd.randint(5000000, 30000000), image_topic, image_msg(t, grey, encoding)))

    imu = [(int(r[0]), [float(v) for v in r[1:4]], [float(v) for v in r[4:7]])
           for r in rows(os.path.join(mav, 'imu0', 'data.csv'))]
    if a.layout == 'openloris':
        ts = np.array([s[0] for s in imu], dtype=np.int64)
        acc = np.array([s[2] for s in imu])
        for t, g, _ in imu:  # gyro at the ASL rate (400 Hz)
            records.append((t + rnd.randint(0, 3000000), '/d400/gyro/sample', imu_msg(t, g, [0, 0, 0])))
        t = int(ts[0]) + 1000000  # accelerometer at 250 Hz, not aligned with the gyro
        while t <= ts[-1]:
            a_t = [float(np.interp(t, ts, acc[:, k])) for k in range(3)]
            records.append((t + rnd.randint(0, 3000000), '/d400/accel/sample', imu_msg(t, [0, 0, 0], a_t)))
            t += 4000000
    else:
        for t, g, acc in imu:
            records.append((t + rnd.randint(0, 3000000), '/imu0', imu_msg(t, g, acc)))

    if a.layout == 'viode':
        for r in rows(os.path.join(mav, 'state_groundtruth_estimate0', 'data.csv')):
            t = int(r[0])
            m = Odometry()
            m.header.stamp = stamp(t)
            m.header.frame_id = 'world'
            m.child_frame_id = 'body'
            m.pose.pose.position.x, m.pose.pose.position.y, m.pose.pose.position.z = map(float, r[1:4])
            qw, qx, qy, qz = map(float, r[4:8])
            m.pose.pose.orientation = Quaternion(qx, qy, qz, qw)
            records.append((t + rnd.randint(0, 3000000), '/odometry', m))

    records.sort(key=lambda r: r[0])
    with rosbag.Bag(a.bag, 'w', compression=a.compression) as bag:
        for t, topic, msg in records:
            bag.write(topic, msg, t=stamp(t))
    return 0


if __name__ == '__main__':
    sys.exit(main())
