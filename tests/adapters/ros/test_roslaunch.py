#!/usr/bin/python3
"""roslaunch of adapters/ros/launch/rfidray_bridge.launch starts the bridge: with a ROS master of its own (a
port from our pid), gazebo:=false (Gazebo 11 is not in Debian 12), the launch file's arguments arrive as the
node's ROS parameters, and the bridge registers with the master as /rfidray, subscribed to /gazebo/model_states,
/tf, /tf_static and /clock (use_sim_time from the launch file) and publishing rfid_sensor/TagArray on the seed
plugin's /gazebo/<antenna>/data topics.

Usage: test_roslaunch.py ROSLAUNCH ROSMASTER ROS_PACKAGE_DIR SOURCE_DIR   (run by ctest, Debian's /usr/bin/python3)
"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import xmlrpc.client


def main():
    roslaunch, rosmaster, package_dir, source = sys.argv[1:5]
    work = tempfile.mkdtemp(prefix="rfidray_roslaunch_")
    port = 20000 + (os.getpid() * 13 + 5) % 20000
    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_IP="127.0.0.1", ROS_HOME=work,
               ROS_PACKAGE_PATH=package_dir)
    master = subprocess.Popen([rosmaster, "--core", "-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.STDOUT)
    launch = None
    log = os.path.join(work, "roslaunch.log")
    try:
        api = xmlrpc.client.ServerProxy(env["ROS_MASTER_URI"])
        deadline = time.time() + 15
        while True:
            try:
                api.getSystemState("/test")
                break
            except OSError:
                if time.time() > deadline:
                    sys.exit("rosmaster did not come up on port %d" % port)
                time.sleep(0.05)
        world = os.path.join(source, "tests/adapters/ros/paper_robot.world")
        with open(log, "w") as out:
            # The package name, as a user runs it: ROS_PACKAGE_PATH holds the build's ros_package.
            launch = subprocess.Popen(
                [roslaunch, "rfidray", "rfidray_bridge.launch", "gazebo:=false", "world:=" + world, "seed:=7",
                 "frames:={mobile: mast_link}", "csv:=" + os.path.join(work, "csv")],
                env=env, stdout=out, stderr=subprocess.STDOUT)
        want_pub = {"/gazebo/mobile/data", "/gazebo/fixed/data"}
        want_sub = {"/gazebo/model_states", "/tf", "/tf_static", "/clock"}
        deadline = time.time() + 30
        while True:
            _, _, state = api.getSystemState("/test")
            pubs = {t for t, nodes in state[0] if "/rfidray" in nodes}
            subs = {t for t, nodes in state[1] if "/rfidray" in nodes}
            if want_pub <= pubs and want_sub <= subs:
                break
            if launch.poll() is not None or time.time() > deadline:
                sys.exit("the bridge did not come up (publishes %s, subscribes %s); roslaunch log:\n%s"
                         % (sorted(pubs), sorted(subs), open(log).read()))
            time.sleep(0.1)
        _, _, seed = api.getParam("/test", "/rfidray/seed")
        _, _, frames = api.getParam("/test", "/rfidray/frame")
        _, _, sim = api.getParam("/test", "/use_sim_time")
        assert seed == 7, seed
        assert frames == {"mobile": "mast_link"}, frames
        assert sim is True, sim
        # The bridge's own account of what it took from the parameters.
        deadline = time.time() + 10
        while "TF world -> mast_link" not in open(log).read() and time.time() < deadline:
            time.sleep(0.1)
        text = open(log).read()
        for expected in ("time from /clock (use_sim_time)", "antenna 'mobile': TF world -> mast_link",
                         "antenna 'fixed': follows its model in /gazebo/model_states"):
            if expected not in text:
                sys.exit("missing in the bridge's output: %r\n%s" % (expected, text))
        assert os.path.exists(os.path.join(work, "csv", "mobile.csv")), "~csv not applied"
        print("roslaunch started the bridge: /rfidray publishes %s" % sorted(want_pub))
    finally:
        if launch is not None and launch.poll() is None:
            launch.send_signal(signal.SIGINT)
            try:
                launch.wait(15)
            except subprocess.TimeoutExpired:
                launch.kill()
                launch.wait()
        master.send_signal(signal.SIGINT)
        try:
            master.wait(10)
        except subprocess.TimeoutExpired:
            master.kill()
            master.wait()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
