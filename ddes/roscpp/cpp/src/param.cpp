// ddes roscpp: parameters (ros::param and the protocol's tagged values).
#include "ddes_core.h"
#include "param_impl.h"

#include <cmath>

#include <ros/names.h>
#include <ros/param.h>
#include <ros/this_node.h>

namespace ros
{
namespace ddes
{

namespace
{

constexpr int kMaxDepth = 64;

enum Tag : uint8_t
{
  TAG_NONE = 0,
  TAG_BOOL = 1,
  TAG_INT = 2,
  TAG_DOUBLE = 3,
  TAG_STRING = 4,
  TAG_ARRAY = 5,
  TAG_STRUCT = 6,
  TAG_BASE64 = 7,
};

// roscpp's xml_castable / xml_cast (param.cpp): numbers and bools convert into one another
template <class T>
bool castable(int type);
template <>
bool castable<std::string>(int type)
{
  return type == XmlRpc::XmlRpcValue::TypeString;
}
template <class T>
bool numberCastable(int type)
{
  return type == XmlRpc::XmlRpcValue::TypeDouble || type == XmlRpc::XmlRpcValue::TypeInt ||
         type == XmlRpc::XmlRpcValue::TypeBoolean;
}
template <>
bool castable<double>(int type)
{
  return numberCastable<double>(type);
}
template <>
bool castable<float>(int type)
{
  return numberCastable<float>(type);
}
template <>
bool castable<int>(int type)
{
  return numberCastable<int>(type);
}
template <>
bool castable<bool>(int type)
{
  return numberCastable<bool>(type);
}

template <class T>
T cast(const XmlRpc::XmlRpcValue& v)
{
  switch (v.getType())
  {
    case XmlRpc::XmlRpcValue::TypeDouble:
      return static_cast<T>(static_cast<const double&>(v));
    case XmlRpc::XmlRpcValue::TypeInt:
      return static_cast<T>(static_cast<const int&>(v));
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return static_cast<T>(static_cast<const bool&>(v));
    default:
      return T();
  }
}
template <>
std::string cast<std::string>(const XmlRpc::XmlRpcValue& v)
{
  return static_cast<const std::string&>(v);
}
template <>
bool cast<bool>(const XmlRpc::XmlRpcValue& v)
{
  switch (v.getType())
  {
    case XmlRpc::XmlRpcValue::TypeDouble:
      return static_cast<const double&>(v) != 0.0;
    case XmlRpc::XmlRpcValue::TypeInt:
      return static_cast<const int&>(v) != 0;
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return static_cast<const bool&>(v);
    default:
      return false;
  }
}

template <class T>
XmlRpc::XmlRpcValue vectorValue(const std::vector<T>& vec)
{
  XmlRpc::XmlRpcValue out;
  out.setSize(static_cast<int>(vec.size()));
  for (size_t i = 0; i < vec.size(); ++i)
    out[static_cast<int>(i)] = XmlRpc::XmlRpcValue(vec[i]);
  return out;
}

XmlRpc::XmlRpcValue vectorValue(const std::vector<float>& vec)
{
  XmlRpc::XmlRpcValue out;
  out.setSize(static_cast<int>(vec.size()));
  for (size_t i = 0; i < vec.size(); ++i)
    out[static_cast<int>(i)] = XmlRpc::XmlRpcValue(static_cast<double>(vec[i]));
  return out;
}

XmlRpc::XmlRpcValue vectorValue(const std::vector<bool>& vec)
{
  XmlRpc::XmlRpcValue out;
  out.setSize(static_cast<int>(vec.size()));
  for (size_t i = 0; i < vec.size(); ++i)
    out[static_cast<int>(i)] = XmlRpc::XmlRpcValue(static_cast<bool>(vec[i]));
  return out;
}

template <class T>
XmlRpc::XmlRpcValue mapValue(const std::map<std::string, T>& map)
{
  XmlRpc::XmlRpcValue out;
  out.begin();  // makes it a struct, as roscpp does
  for (typename std::map<std::string, T>::const_iterator it = map.begin(); it != map.end(); ++it)
    out[it->first] = XmlRpc::XmlRpcValue(static_cast<typename std::conditional<std::is_same<T, float>::value, double, T>::type>(it->second));
  return out;
}

template <class T>
bool getVector(const std::string& ns, const std::string& key, std::vector<T>& vec, bool cached)
{
  XmlRpc::XmlRpcValue v;
  if (!paramGet(ns, key, v, cached))
    return false;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray)
    return false;
  vec.resize(v.size());
  for (int i = 0; i < v.size(); ++i)
  {
    if (!castable<T>(v[i].getType()))
      return false;
    vec[i] = cast<T>(v[i]);
  }
  return true;
}

template <class T>
bool getMap(const std::string& ns, const std::string& key, std::map<std::string, T>& map, bool cached)
{
  XmlRpc::XmlRpcValue v;
  if (!paramGet(ns, key, v, cached))
    return false;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeStruct)
    return false;
  for (XmlRpc::XmlRpcValue::const_iterator it = v.begin(); it != v.end(); ++it)
  {
    if (!castable<T>(it->second.getType()))
      return false;
    map[it->first] = cast<T>(it->second);
  }
  return true;
}

std::string timeText(const struct tm& t)
{
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%04d%02d%02dT%02d:%02d:%02d", t.tm_year, t.tm_mon, t.tm_mday, t.tm_hour, t.tm_min,
                t.tm_sec);
  return buf;
}

}  // namespace

void writeValue(Writer& w, const XmlRpc::XmlRpcValue& v)
{
  switch (v.getType())
  {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      w.u8(TAG_BOOL).u8(static_cast<const bool&>(v) ? 1 : 0);
      break;
    case XmlRpc::XmlRpcValue::TypeInt:
      w.u8(TAG_INT).i32(static_cast<const int&>(v));
      break;
    case XmlRpc::XmlRpcValue::TypeDouble:
      w.u8(TAG_DOUBLE).f64(static_cast<const double&>(v));
      break;
    case XmlRpc::XmlRpcValue::TypeString:
      w.u8(TAG_STRING).str(static_cast<const std::string&>(v));
      break;
    case XmlRpc::XmlRpcValue::TypeDateTime:
      // the protocol has no date-time: its XML-RPC text (iso8601) goes as a string
      w.u8(TAG_STRING).str(timeText(static_cast<const struct tm&>(v)));
      break;
    case XmlRpc::XmlRpcValue::TypeBase64:
    {
      const XmlRpc::XmlRpcValue::BinaryData& b = v;
      w.u8(TAG_BASE64).blob(b.data(), b.size());
      break;
    }
    case XmlRpc::XmlRpcValue::TypeArray:
      w.u8(TAG_ARRAY).u32(static_cast<uint32_t>(v.size()));
      for (int i = 0; i < v.size(); ++i)
        writeValue(w, v[i]);
      break;
    case XmlRpc::XmlRpcValue::TypeStruct:
      w.u8(TAG_STRUCT).u32(static_cast<uint32_t>(v.size()));
      for (XmlRpc::XmlRpcValue::const_iterator it = v.begin(); it != v.end(); ++it)
      {
        w.str(it->first);
        writeValue(w, it->second);
      }
      break;
    default:
      w.u8(TAG_NONE);
  }
}

XmlRpc::XmlRpcValue readValue(Reader& r, int depth)
{
  if (depth > kMaxDepth)
    throw ReplyError("a parameter value nests too deep");
  XmlRpc::XmlRpcValue out;
  switch (r.u8())
  {
    case TAG_NONE:
      break;
    case TAG_BOOL:
      out = XmlRpc::XmlRpcValue(r.u8() != 0);
      break;
    case TAG_INT:
      out = XmlRpc::XmlRpcValue(static_cast<int>(r.i32()));
      break;
    case TAG_DOUBLE:
      out = XmlRpc::XmlRpcValue(r.f64());
      break;
    case TAG_STRING:
      out = XmlRpc::XmlRpcValue(r.str());
      break;
    case TAG_ARRAY:
    {
      uint32_t n = r.u32();
      if (n > r.left())
        throw ReplyError("a parameter array claims more items than its frame holds");
      out.setSize(static_cast<int>(n));
      for (uint32_t i = 0; i < n; ++i)
        out[static_cast<int>(i)] = readValue(r, depth + 1);
      break;
    }
    case TAG_STRUCT:
    {
      uint32_t n = r.u32();
      if (n > r.left())
        throw ReplyError("a parameter struct claims more members than its frame holds");
      out.begin();
      for (uint32_t i = 0; i < n; ++i)
      {
        std::string key = r.str();
        out[key] = readValue(r, depth + 1);
      }
      break;
    }
    case TAG_BASE64:
    {
      uint32_t n = 0;
      const uint8_t* p = r.blob(n);
      out = XmlRpc::XmlRpcValue(const_cast<uint8_t*>(p), static_cast<int>(n));
      break;
    }
    default:
      throw ReplyError("a parameter value of unknown tag");
  }
  return out;
}

XmlRpc::XmlRpcValue toXmlRpc(const XmlRpc::XmlRpcValue& v) { return v; }
XmlRpc::XmlRpcValue toXmlRpc(const std::string& v) { return XmlRpc::XmlRpcValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const char* v) { return XmlRpc::XmlRpcValue(std::string(v)); }
XmlRpc::XmlRpcValue toXmlRpc(double v) { return XmlRpc::XmlRpcValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(int v) { return XmlRpc::XmlRpcValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(bool v) { return XmlRpc::XmlRpcValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<std::string>& v) { return vectorValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<double>& v) { return vectorValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<float>& v) { return vectorValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<int>& v) { return vectorValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<bool>& v) { return vectorValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, std::string>& v) { return mapValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, double>& v) { return mapValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, float>& v) { return mapValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, int>& v) { return mapValue(v); }
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, bool>& v) { return mapValue(v); }

void paramSet(const std::string& ns, const std::string& key, const XmlRpc::XmlRpcValue& v)
{
  requireInit("using the parameter server");
  if (!live())
    return;
  Writer w = Writer::request();
  w.str(ns).str(key);
  writeValue(w, v);
  try
  {
    request(PARAM_SET, w);
  }
  catch (ReplyError&)
  {
    // roscpp's set says nothing when the master refuses
  }
}

bool paramGet(const std::string& ns, const std::string& key, XmlRpc::XmlRpcValue& v, bool cached)
{
  requireInit("using the parameter server");
  if (!live())
    return false;
  Writer w = Writer::request();
  w.str(ns).str(key).u8(cached ? 1 : 0);
  try
  {
    Reader r = request(PARAM_GET, w);
    if (r.u8() == 0)
      return false;
    v = readValue(r);
    return true;
  }
  catch (ReplyError&)
  {
    return false;
  }
}

namespace
{
bool boolQuery(uint8_t kind, const std::string& ns, const std::string& key)
{
  requireInit("using the parameter server");
  if (!live())
    return false;
  Writer w = Writer::request();
  w.str(ns).str(key);
  try
  {
    return request(kind, w).u8() != 0;
  }
  catch (ReplyError&)
  {
    return false;
  }
}
}  // namespace

bool paramHas(const std::string& ns, const std::string& key)
{
  return boolQuery(PARAM_HAS, ns, key);
}

bool paramDelete(const std::string& ns, const std::string& key)
{
  return boolQuery(PARAM_DELETE, ns, key);
}

bool paramSearch(const std::string& ns, const std::string& key, std::string& result)
{
  requireInit("using the parameter server");
  if (!live())
    return false;
  Writer w = Writer::request();
  w.str(ns).str(key);
  try
  {
    Reader r = request(PARAM_SEARCH, w);
    bool found = r.u8() != 0;
    std::string full = r.str();
    if (found)
      result = full;
    return found;
  }
  catch (ReplyError&)
  {
    return false;
  }
}

bool paramNames(std::vector<std::string>& keys)
{
  requireInit("using the parameter server");
  if (!live())
    return false;
  Writer w = Writer::request();
  Reader r = request(PARAM_NAMES, w);
  uint32_t n = r.u32();
  keys.clear();
  for (uint32_t i = 0; i < n; ++i)
    keys.push_back(r.str());
  return true;
}

bool paramGetAs(const std::string& ns, const std::string& key, XmlRpc::XmlRpcValue& v, bool cached)
{
  return paramGet(ns, key, v, cached);
}

bool paramGetAs(const std::string& ns, const std::string& key, std::string& s, bool cached)
{
  XmlRpc::XmlRpcValue v;
  if (!paramGet(ns, key, v, cached) || v.getType() != XmlRpc::XmlRpcValue::TypeString)
    return false;
  s = static_cast<const std::string&>(v);
  return true;
}

bool paramGetAs(const std::string& ns, const std::string& key, double& d, bool cached)
{
  XmlRpc::XmlRpcValue v;
  if (!paramGet(ns, key, v, cached))
    return false;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    d = static_cast<const int&>(v);
  else if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    d = static_cast<const double&>(v);
  else
    return false;
  return true;
}

bool paramGetAs(const std::string& ns, const std::string& key, float& f, bool cached)
{
  double d = static_cast<double>(f);
  if (!paramGetAs(ns, key, d, cached))
    return false;
  f = static_cast<float>(d);
  return true;
}

bool paramGetAs(const std::string& ns, const std::string& key, int& i, bool cached)
{
  XmlRpc::XmlRpcValue v;
  if (!paramGet(ns, key, v, cached))
    return false;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
  {
    // roscpp rounds by the fraction's size
    double d = static_cast<const double&>(v);
    d = std::fmod(d, 1.0) < 0.5 ? std::floor(d) : std::ceil(d);
    i = static_cast<int>(d);
  }
  else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
  {
    i = static_cast<const int&>(v);
  }
  else
  {
    return false;
  }
  return true;
}

bool paramGetAs(const std::string& ns, const std::string& key, bool& b, bool cached)
{
  XmlRpc::XmlRpcValue v;
  if (!paramGet(ns, key, v, cached) || v.getType() != XmlRpc::XmlRpcValue::TypeBoolean)
    return false;
  b = static_cast<const bool&>(v);
  return true;
}

#define DDES_GET_CONTAINER(Type, impl) \
  bool paramGetAs(const std::string& ns, const std::string& key, Type& v, bool cached) \
  { \
    return impl(ns, key, v, cached); \
  }

DDES_GET_CONTAINER(std::vector<std::string>, getVector)
DDES_GET_CONTAINER(std::vector<double>, getVector)
DDES_GET_CONTAINER(std::vector<float>, getVector)
DDES_GET_CONTAINER(std::vector<int>, getVector)
DDES_GET_CONTAINER(std::vector<bool>, getVector)
DDES_GET_CONTAINER(std::map<std::string DDES_COMMA std::string>, getMap)
DDES_GET_CONTAINER(std::map<std::string DDES_COMMA double>, getMap)
DDES_GET_CONTAINER(std::map<std::string DDES_COMMA float>, getMap)
DDES_GET_CONTAINER(std::map<std::string DDES_COMMA int>, getMap)
DDES_GET_CONTAINER(std::map<std::string DDES_COMMA bool>, getMap)

#undef DDES_GET_CONTAINER

}  // namespace ddes

namespace param
{

namespace
{
/// ros::param's keys are read in the node's namespace; "~key" is the node's private one.
std::string key_of(const std::string& key)
{
  ddes::requireInit("using the parameter server");
  return ddes::nodeRelative(key);
}
const std::string& ns_of()
{
  return ddes::state().ns;
}
}  // namespace

#define DDES_PARAM_SET(Type) \
  void set(const std::string& key, Type v) { ddes::paramSet(ns_of(), key_of(key), ddes::toXmlRpc(v)); }

DDES_PARAM_SET(const XmlRpc::XmlRpcValue&)
DDES_PARAM_SET(const std::string&)
DDES_PARAM_SET(const char*)
DDES_PARAM_SET(double)
DDES_PARAM_SET(int)
DDES_PARAM_SET(bool)
DDES_PARAM_SET(const std::vector<std::string>&)
DDES_PARAM_SET(const std::vector<double>&)
DDES_PARAM_SET(const std::vector<float>&)
DDES_PARAM_SET(const std::vector<int>&)
DDES_PARAM_SET(const std::vector<bool>&)
DDES_PARAM_SET(const std::map<std::string DDES_COMMA std::string>&)
DDES_PARAM_SET(const std::map<std::string DDES_COMMA double>&)
DDES_PARAM_SET(const std::map<std::string DDES_COMMA float>&)
DDES_PARAM_SET(const std::map<std::string DDES_COMMA int>&)
DDES_PARAM_SET(const std::map<std::string DDES_COMMA bool>&)

#define DDES_PARAM_GET(Type) \
  bool get(const std::string& key, Type& v) { return ddes::paramGetAs(ns_of(), key_of(key), v, false); } \
  bool getCached(const std::string& key, Type& v) { return ddes::paramGetAs(ns_of(), key_of(key), v, true); }

DDES_PARAM_GET(std::string)
DDES_PARAM_GET(double)
DDES_PARAM_GET(float)
DDES_PARAM_GET(int)
DDES_PARAM_GET(bool)
DDES_PARAM_GET(XmlRpc::XmlRpcValue)
DDES_PARAM_GET(std::vector<std::string>)
DDES_PARAM_GET(std::vector<double>)
DDES_PARAM_GET(std::vector<float>)
DDES_PARAM_GET(std::vector<int>)
DDES_PARAM_GET(std::vector<bool>)
DDES_PARAM_GET(std::map<std::string DDES_COMMA std::string>)
DDES_PARAM_GET(std::map<std::string DDES_COMMA double>)
DDES_PARAM_GET(std::map<std::string DDES_COMMA float>)
DDES_PARAM_GET(std::map<std::string DDES_COMMA int>)
DDES_PARAM_GET(std::map<std::string DDES_COMMA bool>)

#undef DDES_PARAM_SET
#undef DDES_PARAM_GET

bool has(const std::string& key)
{
  return ddes::paramHas(ns_of(), key_of(key));
}

bool del(const std::string& key)
{
  return ddes::paramDelete(ns_of(), key_of(key));
}

bool search(const std::string& key, std::string& result)
{
  // roscpp searches from the node's name: its private namespace first
  return search(this_node::getName(), key, result);
}

bool search(const std::string& ns, const std::string& key, std::string& result)
{
  ddes::requireInit("using the parameter server");
  return ddes::paramSearch(ns, key, result);
}

bool getParamNames(std::vector<std::string>& keys)
{
  return ddes::paramNames(keys);
}

}  // namespace param
}  // namespace ros
