"""ddes.roscpp.gencpp and the C++ runtime headers, compiled and run.

One C++ program (``_PROGRAM``) fills messages of every kind, prints their serialized bytes,
md5 sums, type names, definitions and ``operator<<`` texts, and runs rostime arithmetic.
Compiled against ddes's headers it is compared with ddes's Python side (``ddes.msg``); the
tests marked ``ros`` compile the same source against real ROS (the gencpp headers in
/usr/include, real gencpp for the rest, librostime) and compare the two outputs.  A second
program (``_EXTRAS``) checks what only ddes's headers have; one more compile includes every
header of the bundled packages.

Each compile happens once per test session (across xdist workers too: the first worker to
need a build makes it under a lock, the others reuse it).
"""

from __future__ import annotations

import fcntl
import os
import shutil
import subprocess
import sys
import textwrap
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from ddes.errors import MsgNotFound
from ddes.msg import Message, MessageRegistry, default_registry, serialize_message
from ddes.roscpp import gencpp
from ddes.time.rostime import Duration, Time

CXX = shutil.which("g++")
BOOST = Path("/usr/include/boost/shared_ptr.hpp")
REAL_ROS = Path("/usr/include/ros/ros.h")
REAL_GENCPP = Path("/usr/lib/python3/dist-packages/gencpp/__init__.py")
REAL_TEMPLATES = Path("/usr/share/gencpp")
BUNDLED = Path(gencpp.__file__).resolve().parents[1] / "packages"

pytestmark = pytest.mark.skipif(CXX is None or not BOOST.exists(),
                                reason="needs g++ and the Boost headers")

_EVERYTHING = """\
# ddes gencpp test: every kind of field and constant
int8 I8_MIN=-128
uint8 U8_MAX=255
byte BYTE_C=-7
char CHAR_C=65
int16 I16=-300
uint16 U16=60000
int32 I32=-70000
uint32 U32=4000000000
int64 I64=-9000000000
uint64 U64=9000000000000000000
float32 F32=1.5
float64 F64=-0.125
float64 TINY=1e-05
bool FLAG=True
string GREETING=hello "world" \\ # not a comment
Header header
bool b
byte by
char ch
int8 i8
uint8 u8
int16 i16
uint16 u16
int32 i32
uint32 u32
int64 i64
uint64 u64
float32 f32
float64 f64
string s
time t
duration d
uint8[] u8s
uint8[4] u8f
bool[] bs
bool[3] bf
int8[] i8s
float64[2] f64f
string[] ss
string[2] sf
time[2] tf
duration[] ds
geometry_msgs/Point[] pts
geometry_msgs/Point[2] ptf
std_msgs/Empty e
Inner inner
Inner[] inners
"""

_INNER = """\
string name
int32[] values
geometry_msgs/Point p
geometry_msgs/Point[] pts
"""

# ddes only (real gencpp writes code for these that does not compile)
_WIDE = """\
int64 NEG=-1
int64 LOWEST=-9223372036854775808
uint64 BIG=18446744073709551615
float32 NOT_A_NUMBER=nan
float64 NEG_INF=-inf
"""

_KEYWORDS = """\
int32 class
string new
float64 operator
"""

_TEST_PKG = "ddes_gencpp_test"

# The types the shared program uses (and its includes).
_TYPES = ["std_msgs/String", "std_msgs/Header", "geometry_msgs/PoseStamped",
          "geometry_msgs/PoseWithCovariance", "sensor_msgs/LaserScan",
          "actionlib_msgs/GoalStatus", "roscpp_tutorials/TwoInts", "actionlib/TwoInts",
          f"{_TEST_PKG}/Everything"]

_PROGRAM = r"""
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <actionlib/TwoIntsActionGoal.h>
#include <actionlib_msgs/GoalStatus.h>
#include <ddes_gencpp_test/Everything.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/PoseWithCovariance.h>
#include <roscpp_tutorials/TwoInts.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/Header.h>
#include <std_msgs/String.h>

static void emit(const std::string& key, const std::string& value)
{
  std::cout << "@" << key << " " << value.size() << "\n" << value << "\n";
}

template <class M> std::vector<uint8_t> bytes(const M& m)
{
  const uint32_t n = ros::serialization::serializationLength(m);
  std::vector<uint8_t> buf(n + 1);
  ros::serialization::OStream s(buf.data(), n);
  ros::serialization::serialize(s, m);
  buf.resize(n);
  return buf;
}

static std::string hex(const std::vector<uint8_t>& b)
{
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (uint8_t c : b) { out += digits[c >> 4]; out += digits[c & 15]; }
  return out;
}

template <class M> void report(const std::string& name, const M& m)
{
  std::vector<uint8_t> b = bytes(m);
  emit(name + ".bytes", hex(b));
  emit(name + ".md5", ros::message_traits::md5sum<M>());
  emit(name + ".datatype", ros::message_traits::datatype<M>());
  emit(name + ".definition", ros::message_traits::definition<M>());
  std::ostringstream printed;
  printed << m;
  emit(name + ".print", printed.str());
  emit(name + ".traits", std::string(ros::message_traits::isFixedSize<M>() ? "fixed" : "variable") +
                         (ros::message_traits::hasHeader<M>() ? " header" : ""));
  M back;
  b.push_back(0);
  ros::serialization::IStream in(b.data(), static_cast<uint32_t>(b.size() - 1));
  ros::serialization::deserialize(in, back);
  emit(name + ".roundtrip", hex(bytes(back)) == hex(bytes(m)) ? "same" : "different");
  if (b.size() > 1)
  {
    M cut;
    ros::serialization::IStream short_in(b.data(), static_cast<uint32_t>(b.size() - 2));
    try { ros::serialization::deserialize(short_in, cut); emit(name + ".overrun", "none"); }
    catch (const ros::serialization::StreamOverrunException& e) { emit(name + ".overrun", e.what()); }
  }
}

template <class F> void check(std::ostream& o, const char* label, F f)
{
  o << label << ": ";
  try { f(o); } catch (const std::exception& e) { o << "EXC " << e.what(); }
  o << "\n";
}

static std::string timeChecks()
{
  using ros::Duration;
  using ros::Time;
  std::ostringstream o;
  o << std::setprecision(17);
  check(o, "normalised", [](std::ostream& o) { o << Time(5, 2000000001); });
  check(o, "from 1.5", [](std::ostream& o) { o << Time(1.5); });
  check(o, "rounds up", [](std::ostream& o) { o << Time(0.9999999999); });
  check(o, "rounds down", [](std::ostream& o) { o << Time(1e-10); });
  check(o, "negative", [](std::ostream& o) { o << Time(-1.0); });
  check(o, "too late", [](std::ostream& o) { o << Time(4294967296.0); });
  check(o, "nsec carry", [](std::ostream& o) { o << Time(4294967295u, 1000000000u); });
  check(o, "t - t", [](std::ostream& o) { Duration d = Time(10, 0) - Time(12, 5); o << d << " " << d.sec << " " << d.nsec; });
  check(o, "t - d", [](std::ostream& o) { o << Time(3, 1) - Duration(1, 2); });
  check(o, "t - d < 0", [](std::ostream& o) { o << Time(1, 0) - Duration(2, 0); });
  check(o, "t + d", [](std::ostream& o) { o << Time(1, 999999999) + Duration(0, 2); });
  check(o, "max + 1", [](std::ostream& o) { o << ros::TIME_MAX + Duration(0, 1); });
  check(o, "limits", [](std::ostream& o) { o << ros::TIME_MAX << " " << ros::TIME_MIN << " " << ros::DURATION_MAX << " " << ros::DURATION_MIN; });
  check(o, "d -1.5", [](std::ostream& o) { Duration d(-1.5); o << d << " " << d.sec << " " << d.nsec; });
  check(o, "d -0.5", [](std::ostream& o) { o << Duration(-0.5); });
  check(o, "d -1ns", [](std::ostream& o) { Duration d(0, -1); o << d << " " << d.sec << " " << d.nsec; });
  check(o, "d norm", [](std::ostream& o) { Duration d(5, -2000000001); o << d << " " << d.sec << " " << d.nsec; });
  check(o, "d -1e-10", [](std::ostream& o) { o << Duration(-1e-10); });
  check(o, "d scale", [](std::ostream& o) { o << Duration(1.0) * 2.5 << " " << Duration(3, 0) * -0.5; });
  check(o, "d max + 1", [](std::ostream& o) { o << ros::DURATION_MAX + Duration(0, 1); });
  check(o, "-d min", [](std::ostream& o) { o << -ros::DURATION_MIN; });
  check(o, "d too long", [](std::ostream& o) { o << Duration(2147483648.0); });
  check(o, "d too short", [](std::ostream& o) { o << Duration(-2147483649.0); });
  check(o, "d pair max", [](std::ostream& o) { o << Duration(2147483647, 1000000000); });
  check(o, "to sec", [](std::ostream& o) { o << Time(3, 500000000).toSec() << " " << Duration(-2, 500000000).toSec(); });
  check(o, "to nsec", [](std::ostream& o) { o << Time(3, 500000000).toNSec() << " " << Duration(-2, 500000000).toNSec(); });
  check(o, "from nsec", [](std::ostream& o) { Time t; Duration d; o << t.fromNSec(12345678901234ULL) << " " << d.fromNSec(-1500000000LL); });
  check(o, "t from nsec big", [](std::ostream& o) { Time t; o << t.fromNSec(4294967296000000000ULL); });
  check(o, "compare", [](std::ostream& o) {
    o << (Time(1, 5) < Time(1, 6)) << (Time(2, 0) > Time(1, 999999999)) << (Time(1, 1) <= Time(1, 1))
      << (Time(1, 1) >= Time(1, 2)) << (Time(1, 1) == Time(1, 1)) << (Time(1, 1) != Time(1, 1))
      << (Duration(-1, 0) < Duration(0, 0)) << (Duration(0, 5) >= Duration(0, 5)) << (Duration(1, 0) != Duration(0, 1));
  });
  check(o, "compound", [](std::ostream& o) {
    Time t(10, 0); t += Duration(1, 500000000); t -= Duration(0, 700000000);
    Duration d(1, 0); d += Duration(0, 600000000); d -= Duration(3, 0); d *= 2.0;
    o << t << " " << d;
  });
  check(o, "zero", [](std::ostream& o) { o << Time().isZero() << Time(0, 1).isZero() << Duration().isZero() << Duration(-1, 0).isZero(); });
  check(o, "wall", [](std::ostream& o) { o << ros::WallTime(3, 4) << " " << ros::SteadyTime(5, 6) << " " << ros::WallDuration(-1.25) << " " << (ros::WallTime(3, 4) - ros::WallTime(1, 0)); });
  check(o, "stream state", [](std::ostream& o) { o << std::setfill('*') << std::setw(4) << 7 << Time(1, 2) << std::setw(4) << 8 << Duration(-3, 0) << std::setw(4) << 9; });
  check(o, "double", [](std::ostream& o) { o << Time(1e9 + 0.25) << " " << Duration(1234.000000001); });
  return o.str();
}

int main()
{
  std_msgs::String str;
  str.data = "h\xc3\xa9llo \"ddes\"\n\ttab";
  report("string", str);

  std_msgs::Header h;
  h.seq = 7;
  h.stamp = ros::Time(12, 345);
  h.frame_id = "map";
  report("header", h);

  geometry_msgs::PoseStamped ps;
  ps.header = h;
  ps.pose.position.x = 1.5;
  ps.pose.position.y = -2.25;
  ps.pose.position.z = 0.1;
  ps.pose.orientation.w = 1.0;
  report("pose_stamped", ps);

  geometry_msgs::PoseWithCovariance pc;
  for (int i = 0; i < 36; ++i) pc.covariance[i] = i * 0.5;
  pc.pose.orientation.z = 0.7071067811865476;
  report("pose_covariance", pc);

  sensor_msgs::LaserScan scan;
  scan.header.frame_id = "laser";
  scan.header.stamp = ros::Time(3, 500000000);
  scan.angle_min = -1.5f;
  scan.angle_max = 1.5f;
  scan.angle_increment = 0.75f;
  scan.range_min = 0.125f;
  scan.range_max = 30.0f;
  scan.ranges = {1.0f, 2.5f, std::numeric_limits<float>::infinity(), 0.25f};
  report("laser_scan", scan);

  actionlib_msgs::GoalStatus st;
  st.status = actionlib_msgs::GoalStatus::ACTIVE;
  st.goal_id.id = "goal-1";
  st.goal_id.stamp = ros::Time(1, 2);
  st.text = "working";
  report("goal_status", st);
  {
    std::ostringstream o;
    typedef actionlib_msgs::GoalStatus G;
    o << +G::PENDING << " " << +G::ACTIVE << " " << +G::PREEMPTED << " " << +G::SUCCEEDED << " "
      << +G::ABORTED << " " << +G::REJECTED << " " << +G::PREEMPTING << " " << +G::RECALLING << " "
      << +G::RECALLED << " " << +G::LOST;
    emit("goal_status.constants", o.str());
  }

  roscpp_tutorials::TwoInts srv;
  srv.request.a = 3;
  srv.request.b = -4;
  srv.response.sum = -1;
  report("two_ints_request", srv.request);
  report("two_ints_response", srv.response);
  emit("two_ints.md5", ros::service_traits::md5sum<roscpp_tutorials::TwoInts>());
  emit("two_ints.datatype", ros::service_traits::datatype<roscpp_tutorials::TwoInts>());
  emit("two_ints.request_service_md5", ros::service_traits::md5sum(srv.request));
  emit("two_ints.request_service_datatype", ros::service_traits::datatype(srv.request));
  emit("two_ints.response_service_md5", ros::service_traits::md5sum<roscpp_tutorials::TwoIntsResponse>());
  emit("two_ints.response_service_datatype", ros::service_traits::datatype<roscpp_tutorials::TwoInts::Response>());

  actionlib::TwoIntsActionGoal goal;
  goal.header.seq = 1;
  goal.header.stamp = ros::Time(5, 6);
  goal.goal_id.id = "g";
  goal.goal.a = 10;
  goal.goal.b = 20;
  report("action_goal", goal);

  ddes_gencpp_test::Everything e;
  e.header.seq = 3;
  e.header.stamp = ros::Time(100, 200);
  e.header.frame_id = "base";
  e.b = true;
  e.by = -5;
  e.ch = 200;
  e.i8 = -100;
  e.u8 = 250;
  e.i16 = -12345;
  e.u16 = 54321;
  e.i32 = -1234567;
  e.u32 = 3000000000u;
  e.i64 = -1234567890123LL;
  e.u64 = 12345678901234567890ULL;
  e.f32 = 0.5f;
  e.f64 = 3.25;
  e.s = "text";
  e.t = ros::Time(7, 8);
  e.d = ros::Duration(-1, 500000000);
  e.u8s = {1, 2, 255};
  e.u8f = {{9, 8, 7, 6}};
  e.bs = {1, 0, 1};
  e.bf = {{0, 1, 0}};
  e.i8s = {-1, 0, 1};
  e.f64f = {{1.25, -2.5}};
  e.ss = {"a", "bc"};
  e.sf = {{"x", "yz"}};
  e.tf = {{ros::Time(1, 1), ros::Time(2, 2)}};
  e.ds = {ros::Duration(3, 3)};
  geometry_msgs::Point p;
  p.x = 1; p.y = 2; p.z = 3;
  e.pts.push_back(p);
  e.ptf[0].x = 4; e.ptf[0].y = 5; e.ptf[0].z = 6;
  e.ptf[1].x = 7; e.ptf[1].y = 8; e.ptf[1].z = 9;
  e.inner.name = "in";
  e.inner.values = {1, 2, 3};
  e.inner.p.x = 0.5; e.inner.p.y = 0.25; e.inner.p.z = 0.125;
  e.inner.pts.resize(2);
  e.inner.pts[1].y = -1;
  ddes_gencpp_test::Inner i1, i2;
  i1.name = "i1";
  i2.name = "i2";
  i2.values = {4};
  i2.p.x = 1; i2.p.y = 1; i2.p.z = 1;
  e.inners = {i1, i2};
  report("everything", e);
  {
    typedef ddes_gencpp_test::Everything E;
    std::ostringstream o;
    o << std::setprecision(17) << +E::I8_MIN << " " << +E::U8_MAX << " " << +E::BYTE_C << " " << +E::CHAR_C
      << " " << +E::I16 << " " << +E::U16 << " " << +E::I32 << " " << +E::U32 << " " << +E::I64 << " "
      << +E::U64 << " " << E::F32 << " " << E::F64 << " " << E::TINY << " " << +E::FLAG << " ["
      << E::GREETING << "]";
    emit("everything.constants", o.str());
  }

  emit("time", timeChecks());
  return 0;
}
"""

_EXTRAS = r"""
#include <array>
#include <iostream>
#include <sstream>
#include <vector>

#include <ros/assert.h>
#include <ros/serialization.h>
#include <ddes_gencpp_test/Everything.h>
#include <ddes_gencpp_test/Keywords.h>
#include <ddes_gencpp_test/Wide.h>
#include <geometry_msgs/PoseStamped.h>
#include <std_msgs/Empty.h>

namespace ser = ros::serialization;
namespace mt = ros::message_traits;

static std::string hex(const std::vector<uint8_t>& b)
{
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (uint8_t c : b) { out += digits[c >> 4]; out += digits[c & 15]; }
  return out;
}

template <class T> std::vector<uint8_t> bytes(const T& t)
{
  std::vector<uint8_t> buf(ser::serializationLength(t));
  ser::OStream s(buf.data(), static_cast<uint32_t>(buf.size()));
  ser::serialize(s, t);
  return buf;
}

int main()
{
  typedef ddes_gencpp_test::Wide W;
  std::cout << "wide " << +W::NEG << " " << +W::LOWEST << " " << +W::BIG << " "
            << (W::NOT_A_NUMBER != W::NOT_A_NUMBER) << " " << W::NEG_INF << "\n";

  ddes_gencpp_test::Keywords k;
  k.class_ = 5;
  k.new_ = "n";
  k.operator_ = 0.5;
  std::cout << "keywords " << hex(bytes(k)) << "\n" << k;

  std::vector<bool> flags = {true, false, true, true};
  std::vector<bool> flags_back;
  std::vector<uint8_t> fb = bytes(flags);
  ser::IStream fin(fb.data(), static_cast<uint32_t>(fb.size()));
  ser::deserialize(fin, flags_back);
  std::cout << "vector<bool> " << hex(fb) << " " << (flags_back == flags) << "\n";

  std::array<uint16_t, 3> arr = {{1, 2, 0xABCD}};
  std::cout << "std::array " << hex(bytes(arr)) << "\n";
  std::vector<std::string> strs = {"ab", ""};
  std::cout << "vector<string> " << hex(bytes(strs)) << "\n";

  geometry_msgs::PoseStamped ps;
  ps.header.frame_id = "odom";
  ps.header.stamp = ros::Time(4, 5);
  ps.pose.position.x = 2.0;
  std::vector<uint8_t> pb = ser::serializeToBytes(ps);
  geometry_msgs::PoseStamped ps_back;
  ser::deserializeFromBytes(pb, ps_back);
  std::cout << "bytes " << pb.size() << " " << (ps_back == ps) << " " << (ps_back != ps) << "\n";

  ros::SerializedMessage sm = ser::serializeMessage(ps);
  geometry_msgs::PoseStamped ps_sm;
  ser::deserializeMessage(sm, ps_sm);
  std::cout << "serializeMessage " << sm.num_bytes << " " << (sm.message_start - sm.buf.get())
            << " " << hex(std::vector<uint8_t>(sm.buf.get(), sm.buf.get() + 4)) << " " << (ps_sm == ps) << "\n";
  ros::SerializedMessage sr = ser::serializeServiceResponse(true, ps);
  std::cout << "serviceResponse " << sr.num_bytes << " " << +sr.buf[0] << "\n";

  // a count that promises more elements than the bytes left: refused before allocating
  std::vector<uint8_t> evil = {0xF0, 0xFF, 0xFF, 0xFF, 1, 2, 3, 4};
  std::vector<double> huge;
  try { ser::deserializeFromBytes(evil, huge); std::cout << "evil accepted\n"; }
  catch (const ser::StreamOverrunException& e) { std::cout << "evil refused " << e.what() << " " << huge.capacity() << "\n"; }
  std::vector<geometry_msgs::PoseStamped> many;
  try { ser::deserializeFromBytes(evil, many); std::cout << "evil accepted\n"; }
  catch (const ros::Exception& e) { std::cout << "evil refused " << e.what() << "\n"; }

  std::cout << "traits " << mt::IsMessage<geometry_msgs::PoseStamped>::value
            << mt::IsMessage<const geometry_msgs::PoseStamped>::value << mt::IsMessage<int>::value
            << mt::isSimple<uint32_t>() << mt::isSimple<geometry_msgs::Point>()
            << mt::isFixedSize<geometry_msgs::Point>() << mt::isFixedSize<std_msgs::Empty>()
            << mt::hasHeader<const geometry_msgs::PoseStamped&>()
            << (mt::header(ps) == &ps.header) << (mt::header(k) == nullptr)
            << (*mt::frameId(ps) == "odom") << (mt::timeStamp(ps)->sec == 4) << "\n";
  static_assert(std::is_same<geometry_msgs::PoseStamped::Ptr, geometry_msgs::PoseStampedPtr>::value, "Ptr");
  static_assert(std::is_same<geometry_msgs::PoseStamped::ConstPtr, boost::shared_ptr<const geometry_msgs::PoseStamped> >::value, "ConstPtr");
  static_assert(std::is_same<ddes_gencpp_test::Everything::_u8f_type, boost::array<uint8_t, 4> >::value, "fixed array");
  static_assert(std::is_same<ddes_gencpp_test::Everything::_ss_type, std::vector<std::string> >::value, "string array");
  static_assert(mt::MD5Sum<std_msgs::Empty>::static_value1 == 0xd41d8cd98f00b204ULL, "md5 words");
  std_msgs::Empty e1, e2;
  std::cout << "empty " << (e1 == e2) << " [" << e1 << "] " << ser::serializationLength(e1) << "\n";

  ddes_gencpp_test::Everything zero;
  std::cout << "zeroed " << +zero.u8 << zero.f64 << +zero.u8f[3] << +zero.bf[2] << zero.f64f[1] << zero.tf[1]
            << zero.ptf[1].z << zero.sf[1].size() << zero.u8s.size() << zero.inner.values.size() << "\n";
  std::allocator<void> alloc;
  ddes_gencpp_test::Everything with_alloc(alloc);
  std::cout << "with allocator " << (with_alloc == zero) << "\n";
  ROS_ASSERT(zero.u8 == 0);
  ROS_ASSERT_MSG(zero.f64 == 0.0, "f64 is %f", zero.f64);
  ROS_STATIC_ASSERT(sizeof(uint32_t) == 4);
  return 0;
}
"""


# -- builds shared by every test of the session (and every xdist worker) ---------------------
@pytest.fixture(scope="session")
def shared_root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    base = tmp_path_factory.getbasetemp()
    # under xdist each worker has its own base in one folder of the session
    root = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "roscpp_gencpp"
    root.mkdir(parents=True, exist_ok=True)
    return root


def _once(root: Path, name: str, build: Callable[[Path], object]) -> Path:
    """``build(folder)`` run once per session under a lock; later callers get the folder."""
    folder = root / name
    done = folder / ".done"
    with open(root / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():
            shutil.rmtree(folder, ignore_errors=True)
            folder.mkdir()
            build(folder)
            done.touch()
    return folder


def _compile(args: list[str], cwd: Path) -> float:
    """Run a compiler command; its wall time in seconds (a failure shows the errors)."""
    start = time.perf_counter()
    proc = subprocess.run(args, cwd=cwd, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if proc.returncode != 0:
        pytest.fail(f"compile failed ({' '.join(args)}):\n{proc.stderr[-6000:]}")
    (cwd / "compile_seconds").write_text(f"{elapsed:.2f}\n")
    return elapsed


def _parse(stdout: bytes) -> dict[str, str]:
    """The ``@key len\\nvalue\\n`` records the programs print (len in bytes)."""
    out: dict[str, str] = {}
    pos = 0
    while pos < len(stdout):
        head_end = stdout.index(b"\n", pos)
        assert stdout[pos:pos + 1] == b"@", stdout[pos:pos + 80]
        key, _, size = stdout[pos + 1:head_end].decode("ascii").partition(" ")
        start = head_end + 1
        out[key] = stdout[start:start + int(size)].decode("utf-8")
        pos = start + int(size) + 1
    return out


def _write_test_package(folder: Path) -> Path:
    msg = folder / _TEST_PKG / "msg"
    msg.mkdir(parents=True)
    for name, text in (("Everything", _EVERYTHING), ("Inner", _INNER), ("Wide", _WIDE),
                       ("Keywords", _KEYWORDS)):
        (msg / f"{name}.msg").write_text(text, encoding="utf-8")
    return folder


def _registry(root: Path) -> MessageRegistry:
    pkgs = _once(root, "packages", _write_test_package)
    return MessageRegistry([pkgs])


@pytest.fixture(scope="session")
def registry(shared_root: Path) -> MessageRegistry:
    return _registry(shared_root)


@pytest.fixture(scope="session")
def ddes_program(shared_root: Path, registry: MessageRegistry) -> dict[str, str]:
    """_PROGRAM compiled against ddes's headers, run: its records."""

    def build(folder: Path) -> None:
        gen = folder / "gen"
        gencpp.write_headers(registry, _TYPES, gen)
        (folder / "program.cpp").write_text(_PROGRAM, encoding="utf-8")
        _compile([CXX or "g++", "-std=c++17", "-O0", "-Wall", "-Wextra", "-Werror",
                  f"-I{gencpp.INCLUDE_DIR}", f"-I{gen}", "program.cpp", "-o", "program"], folder)
        run = subprocess.run([str(folder / "program")], capture_output=True, check=True)
        (folder / "out.txt").write_bytes(run.stdout)

    folder = _once(shared_root, "ddes_program", build)
    return _parse((folder / "out.txt").read_bytes())


# The headers of real ROS the program includes (the other types real gencpp generates).
_REAL_HEADERS = ["std_msgs/String.h", "std_msgs/Header.h", "geometry_msgs/PoseStamped.h",
                 "geometry_msgs/PoseWithCovariance.h", "actionlib_msgs/GoalStatus.h",
                 "actionlib/TwoIntsActionGoal.h"]


def _real_available() -> str | None:
    if not REAL_ROS.exists():
        return "real ROS 1 (/usr/include/ros/ros.h) is not installed"
    missing = [h for h in _REAL_HEADERS if not (Path("/usr/include") / h).exists()]
    if missing:
        return f"real ROS's message headers are not installed: {', '.join(missing)}"
    if not REAL_GENCPP.exists() or not (REAL_TEMPLATES / "msg.h.template").exists():
        return "real gencpp (python3-gencpp) is not installed"
    probe = subprocess.run(["/usr/bin/python3", "-c", "import em, genmsg.template_tools"],
                           capture_output=True)
    if probe.returncode != 0:
        return "real gencpp cannot run: /usr/bin/python3 lacks em or genmsg"
    return None


@pytest.fixture(scope="session")
def real_program(shared_root: Path, registry: MessageRegistry) -> dict[str, str]:
    """_PROGRAM compiled against real ROS: /usr/include's gencpp headers, real gencpp's for
    the types /usr/include lacks (from ddes's definitions), linked with librostime."""
    why = _real_available()
    if why:
        pytest.skip(why)

    def build(folder: Path) -> None:
        gen = folder / "gen"
        pkgs = _once(shared_root, "packages", _write_test_package)
        msg_dirs = {p.name: p / "msg" for p in BUNDLED.iterdir() if (p / "msg").is_dir()}
        msg_dirs[_TEST_PKG] = pkgs / _TEST_PKG / "msg"
        files = [("sensor_msgs", BUNDLED / "sensor_msgs/msg/LaserScan.msg"),
                 ("roscpp_tutorials", BUNDLED / "roscpp_tutorials/srv/TwoInts.srv"),
                 (_TEST_PKG, pkgs / _TEST_PKG / "msg/Everything.msg"),
                 (_TEST_PKG, pkgs / _TEST_PKG / "msg/Inner.msg")]
        includes = [f"{pkg}:{path}" for pkg, path in sorted(msg_dirs.items())]
        script = textwrap.dedent(f"""
            import genmsg.template_tools as t
            files = {[(pkg, str(path)) for pkg, path in files]!r}
            for pkg, path in files:
                t.generate_from_file(path, pkg, {str(gen)!r} + "/" + pkg, {str(REAL_TEMPLATES)!r},
                                     {includes!r}, {{"msg.h.template": "@NAME@.h"}},
                                     {{"srv.h.template": "@NAME@.h"}})
        """)
        subprocess.run(["/usr/bin/python3", "-c", script], check=True, capture_output=True)
        (folder / "program.cpp").write_text(_PROGRAM, encoding="utf-8")
        _compile([CXX or "g++", "-std=c++17", "-O0", "-w", f"-I{gen}", "program.cpp", "-o",
                  "program", "-lroscpp_serialization", "-lrostime", "-lcpp_common"], folder)
        run = subprocess.run([str(folder / "program")], capture_output=True, check=True)
        (folder / "out.txt").write_bytes(run.stdout)

    folder = _once(shared_root, "real_program", build)
    return _parse((folder / "out.txt").read_bytes())


@pytest.fixture(scope="session")
def extras_output(shared_root: Path, registry: MessageRegistry) -> str:
    def build(folder: Path) -> None:
        gen = folder / "gen"
        gencpp.write_headers(registry, [f"{_TEST_PKG}/Everything", f"{_TEST_PKG}/Wide",
                                        f"{_TEST_PKG}/Keywords", "geometry_msgs/PoseStamped",
                                        "std_msgs/Empty"], gen)
        (folder / "extras.cpp").write_text(_EXTRAS, encoding="utf-8")
        # C++11, pedantic: catkin packages still often say add_compile_options(-std=c++11)
        _compile([CXX or "g++", "-std=c++11", "-Wpedantic", "-O0", "-Wall", "-Wextra",
                  "-Werror", f"-I{gencpp.INCLUDE_DIR}", f"-I{gen}", "extras.cpp", "-o",
                  "extras"], folder)
        run = subprocess.run([str(folder / "extras")], capture_output=True, check=True)
        (folder / "out.txt").write_bytes(run.stdout)

    return (_once(shared_root, "extras", build) / "out.txt").read_text(encoding="utf-8")


# -- the Python side of the program's messages ---------------------------------------------
def _python_messages(registry: MessageRegistry) -> dict[str, Message]:
    get = registry.get_message_class
    Header, Point = get("std_msgs/Header"), get("geometry_msgs/Point")
    Pose, Quaternion = get("geometry_msgs/Pose"), get("geometry_msgs/Quaternion")
    Inner = get(f"{_TEST_PKG}/Inner")
    header = Header(seq=7, stamp=Time(12, 345), frame_id="map")
    two_ints = registry.get_service_class("roscpp_tutorials/TwoInts")
    GoalID = get("actionlib_msgs/GoalID")
    return {
        "string": get("std_msgs/String")(data='h\u00e9llo "ddes"\n\ttab'),
        "header": header,
        "pose_stamped": get("geometry_msgs/PoseStamped")(
            header=header, pose=Pose(position=Point(1.5, -2.25, 0.1),
                                     orientation=Quaternion(0, 0, 0, 1.0))),
        "pose_covariance": get("geometry_msgs/PoseWithCovariance")(
            pose=Pose(orientation=Quaternion(0, 0, 0.7071067811865476, 0)),
            covariance=[i * 0.5 for i in range(36)]),
        "laser_scan": get("sensor_msgs/LaserScan")(
            header=Header(stamp=Time(3, 500000000), frame_id="laser"), angle_min=-1.5,
            angle_max=1.5, angle_increment=0.75, range_min=0.125, range_max=30.0,
            ranges=[1.0, 2.5, float("inf"), 0.25]),
        "goal_status": get("actionlib_msgs/GoalStatus")(
            goal_id=GoalID(stamp=Time(1, 2), id="goal-1"), status=1, text="working"),
        "two_ints_request": two_ints._request_class(a=3, b=-4),
        "two_ints_response": two_ints._response_class(sum=-1),
        "action_goal": get("actionlib/TwoIntsActionGoal")(
            header=Header(seq=1, stamp=Time(5, 6)), goal_id=GoalID(id="g"),
            goal=get("actionlib/TwoIntsGoal")(a=10, b=20)),
        "everything": get(f"{_TEST_PKG}/Everything")(
            header=Header(seq=3, stamp=Time(100, 200), frame_id="base"), b=True, by=-5, ch=200,
            i8=-100, u8=250, i16=-12345, u16=54321, i32=-1234567, u32=3000000000,
            i64=-1234567890123, u64=12345678901234567890, f32=0.5, f64=3.25, s="text",
            t=Time(7, 8), d=Duration(-1, 500000000), u8s=bytes([1, 2, 255]),
            u8f=bytes([9, 8, 7, 6]), bs=[True, False, True], bf=[False, True, False],
            i8s=[-1, 0, 1], f64f=[1.25, -2.5], ss=["a", "bc"], sf=["x", "yz"],
            tf=[Time(1, 1), Time(2, 2)], ds=[Duration(3, 3)], pts=[Point(1, 2, 3)],
            ptf=[Point(4, 5, 6), Point(7, 8, 9)], e=get("std_msgs/Empty")(),
            inner=Inner(name="in", values=[1, 2, 3], p=Point(0.5, 0.25, 0.125),
                        pts=[Point(), Point(0, -1, 0)]),
            inners=[Inner(name="i1"), Inner(name="i2", values=[4], p=Point(1, 1, 1))]),
    }


def _gencpp_definition(full_text: str) -> str:
    """What a gencpp header's Definition holds: each line of the text ending in a newline."""
    return full_text if full_text.endswith("\n") else full_text + "\n"


_NAMES = ["string", "header", "pose_stamped", "pose_covariance", "laser_scan", "goal_status",
          "two_ints_request", "two_ints_response", "action_goal", "everything"]


# -- tests ---------------------------------------------------------------------------------
@pytest.mark.parametrize("name", _NAMES)
def test_cpp_matches_python(name: str, ddes_program: dict[str, str],
                            registry: MessageRegistry) -> None:
    msg = _python_messages(registry)[name]
    cls = type(msg)
    assert ddes_program[f"{name}.bytes"] == serialize_message(msg).hex()
    assert ddes_program[f"{name}.md5"] == cls._md5sum
    assert ddes_program[f"{name}.datatype"] == cls._type
    assert ddes_program[f"{name}.definition"] == _gencpp_definition(cls._full_text)
    assert ddes_program[f"{name}.roundtrip"] == "same"
    assert ddes_program.get(f"{name}.overrun", "Buffer Overrun") == "Buffer Overrun"
    assert ddes_program[f"{name}.traits"].endswith(" header") == cls._has_header


def test_service_traits(ddes_program: dict[str, str], registry: MessageRegistry) -> None:
    srv = registry.get_service_class("roscpp_tutorials/TwoInts")
    for key in ("md5", "request_service_md5", "response_service_md5"):
        assert ddes_program[f"two_ints.{key}"] == srv._md5sum == "6a2e34150c00229791cc89ff309fff21"
    for key in ("datatype", "request_service_datatype", "response_service_datatype"):
        assert ddes_program[f"two_ints.{key}"] == "roscpp_tutorials/TwoInts"
    assert ddes_program["two_ints_request.datatype"] == "roscpp_tutorials/TwoIntsRequest"


def test_print_format(ddes_program: dict[str, str]) -> None:
    assert ddes_program["header.print"] == "seq: 7\nstamp: 12.000000345\nframe_id: map\n"
    assert ddes_program["laser_scan.print"].splitlines()[-6:] == [
        "ranges[]", "  ranges[0]: 1", "  ranges[1]: 2.5", "  ranges[2]: inf",
        "  ranges[3]: 0.25", "intensities[]"]
    printed = ddes_program["everything.print"]
    assert "\nd: -0.500000000\n" in printed
    assert "\nu8s[]\n  u8s[0]: 1\n  u8s[1]: 2\n  u8s[2]: 255\n" in printed  # numbers, not chars
    # gencpp's quirk: an element of a message array has its first line indented twice
    assert "\ninners[]\n  inners[0]: \n    name: i1\n    values[]\n    p: \n" in printed
    assert ("\ninner: \n  name: in\n  values[]\n    values[0]: 1\n    values[1]: 2\n"
            "    values[2]: 3\n  p: \n    x: 0.5\n") in printed
    assert "\n  pts[]\n    pts[0]: \n        x: 0\n      y: 0\n" in printed
    assert ddes_program["everything.constants"] == (
        "-128 255 -7 65 -300 60000 -70000 4000000000 -9000000000 9000000000000000000 1.5 "
        "-0.125 1.0000000000000001e-05 1 [hello \"world\" \\ # not a comment]")
    assert ddes_program["goal_status.constants"] == "0 1 2 3 4 5 6 7 8 9"


def test_time_arithmetic(ddes_program: dict[str, str]) -> None:
    lines = dict(line.split(": ", 1) for line in ddes_program["time"].splitlines())
    assert lines["normalised"] == "7.000000001"
    assert lines["rounds up"] == "1.000000000"
    assert lines["negative"] == "EXC Time is out of dual 32-bit range"
    assert lines["t - t"] == "-2.000000005 -3 999999995"
    assert lines["d -1.5"] == "-1.500000000 -2 500000000"
    assert lines["d -1ns"] == "-0.000000001 -1 999999999"
    assert lines["d max + 1"] == "EXC Duration is out of dual 32-bit range"
    assert lines["limits"] == ("4294967295.999999999 0.000000001 2147483647.999999999 "
                               "-2147483648.000000000")
    assert lines["stream state"] == "***71.000000002***8-3.000000000***9"


def test_extras(extras_output: str) -> None:
    lines = extras_output.splitlines()
    assert lines[0] == "wide -1 -9223372036854775808 18446744073709551615 1 -inf"
    assert lines[1] == "keywords 05000000010000006e000000000000e03f"
    assert lines[2:5] == ["class: 5", "new: n", "operator: 0.5"]
    assert "vector<bool> 0400000001000101 1" in lines
    assert "std::array 01000200cdab" in lines
    assert "vector<string> 02000000020000006162" + "00000000" in lines
    assert "bytes 76 1 0" in lines  # PoseStamped: header 20 bytes (frame "odom"), pose 56
    assert "serializeMessage 80 4 4c000000 1" in lines  # a u32 length first
    assert "serviceResponse 81 1" in lines
    assert "evil refused Buffer Overrun 0" in lines
    assert lines.count("evil refused Buffer Overrun") == 1
    assert "traits 110101111111" in lines
    assert "empty 1 [] 0" in lines
    assert "zeroed 000000.0000000000000" in lines
    assert "with allocator 1" in lines


def test_every_bundled_header_compiles(shared_root: Path) -> None:
    """Every message and service of ddes's bundled packages: generated, included in one
    translation unit, compiled with warnings as errors."""

    def build(folder: Path) -> None:
        paths = gencpp.write_headers(default_registry(), None, folder / "gen")
        includes = "".join(f"#include <{p.relative_to(folder / 'gen').as_posix()}>\n"
                           for p in paths)
        (folder / "all.cpp").write_text(includes + "int main() { return 0; }\n")
        _compile([CXX or "g++", "-std=c++17", "-fsyntax-only", "-Wall", "-Wextra", "-Werror",
                  f"-I{gencpp.INCLUDE_DIR}", f"-I{folder / 'gen'}", "all.cpp"], folder)

    folder = _once(shared_root, "all_headers", build)
    assert len(list((folder / "gen").rglob("*.h"))) > 200


@pytest.mark.ros
@pytest.mark.parametrize("name", _NAMES)
def test_same_as_real_gencpp(name: str, ddes_program: dict[str, str],
                             real_program: dict[str, str]) -> None:
    for key in ("bytes", "md5", "datatype", "definition", "print", "traits", "roundtrip",
                "overrun"):
        assert ddes_program.get(f"{name}.{key}") == real_program.get(f"{name}.{key}"), key


@pytest.mark.ros
def test_same_constants_and_service_traits_as_real(ddes_program: dict[str, str],
                                                   real_program: dict[str, str]) -> None:
    keys = [k for k in real_program if k.startswith("two_ints.") or k.endswith(".constants")]
    assert len(keys) == 8
    assert {k: ddes_program[k] for k in keys} == {k: real_program[k] for k in keys}


@pytest.mark.ros
def test_same_time_arithmetic_as_rostime(ddes_program: dict[str, str],
                                         real_program: dict[str, str]) -> None:
    assert ddes_program["time"].splitlines() == real_program["time"].splitlines()


# -- the generator itself (no compiler needed) ----------------------------------------------
def test_write_only_when_changed(tmp_path: Path) -> None:
    registry = default_registry()
    paths = gencpp.write_headers(registry, ["std_msgs/String"], tmp_path)
    assert paths == [tmp_path / "std_msgs/String.h"]
    before = paths[0].stat().st_mtime_ns
    os.utime(paths[0], ns=(before - 10**9, before - 10**9))
    again = gencpp.write_headers(registry, ["std_msgs/String"], tmp_path)
    assert again == paths and paths[0].stat().st_mtime_ns == before - 10**9
    paths[0].write_text("stale")
    gencpp.write_headers(registry, ["std_msgs/String"], tmp_path)
    assert paths[0].read_text().startswith("// Generated by ddes")


def test_dependencies_and_kinds() -> None:
    registry = default_registry()
    names = [h.relpath for h in gencpp.generate_headers(registry, ["nav_msgs/GetMap"])]
    # a service and an action of one name: both, with every message they use
    for path in ("nav_msgs/GetMap.h", "nav_msgs/GetMapRequest.h", "nav_msgs/GetMapResponse.h",
                 "nav_msgs/GetMapAction.h", "nav_msgs/GetMapActionGoal.h",
                 "nav_msgs/GetMapGoal.h", "nav_msgs/GetMapFeedback.h",
                 "nav_msgs/OccupancyGrid.h", "nav_msgs/MapMetaData.h", "std_msgs/Header.h",
                 "actionlib_msgs/GoalID.h", "actionlib_msgs/GoalStatus.h",
                 "geometry_msgs/Pose.h"):
        assert path in names
    assert names == sorted(names)
    pkg = [h.relpath for h in gencpp.generate_headers(registry, packages=["actionlib_tutorials"])]
    assert "actionlib_tutorials/FibonacciActionGoal.h" in pkg and "std_msgs/Header.h" in pkg
    alone = gencpp.generate_headers(registry, ["nav_msgs/GetMap"], dependencies=False)
    assert [h.relpath for h in alone] == [
        f"nav_msgs/GetMap{s}.h" for s in ("", "Action", "ActionFeedback", "ActionGoal",
                                          "ActionResult", "Feedback", "Goal", "Request",
                                          "Response", "Result")]
    with pytest.raises(MsgNotFound):
        gencpp.generate_headers(registry, ["std_msgs/NoSuchType"])


def test_deterministic_text() -> None:
    first = gencpp.generate_headers(default_registry(), ["sensor_msgs/LaserScan"])
    second = gencpp.generate_headers(MessageRegistry(), ["sensor_msgs/LaserScan"])
    assert first == second
    for header in first:
        assert "/work" not in header.text and str(BUNDLED) not in header.text


def test_command_line(tmp_path: Path, shared_root: Path) -> None:
    pkgs = _once(shared_root, "packages", _write_test_package)
    env = {k: v for k, v in os.environ.items() if k != "DDES_PACKAGE_PATH"}
    cmd = [sys.executable, "-m", "ddes.roscpp.gencpp", "--out", str(tmp_path / "out"),
           "--package-path", str(pkgs)]
    listed = subprocess.run([*cmd, "--list", "--package", _TEST_PKG], capture_output=True,
                            text=True, env=env, check=True)
    assert f"{tmp_path / 'out' / _TEST_PKG / 'Everything.h'}" in listed.stdout.splitlines()
    assert not (tmp_path / "out").exists()
    subprocess.run([*cmd, f"{_TEST_PKG}/Inner"], env=env, check=True)
    assert sorted(p.relative_to(tmp_path / "out").as_posix()
                  for p in (tmp_path / "out").rglob("*.h")) == [
        f"{_TEST_PKG}/Inner.h", "geometry_msgs/Point.h"]
    bad = subprocess.run([*cmd, "nope/Nothing"], capture_output=True, text=True, env=env)
    assert bad.returncode == 1 and "gencpp: error:" in bad.stderr
