// ddes roscpp: XmlRpc::XmlRpcValue.
#include <xmlrpcpp/XmlRpcException.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ostream>
#include <sstream>

namespace XmlRpc
{

std::string XmlRpcValue::_doubleFormat("%.16g");

namespace
{

const char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64Encode(const std::vector<char>& data)
{
  std::string out;
  size_t i = 0;
  while (i + 2 < data.size())
  {
    unsigned v = (static_cast<unsigned char>(data[i]) << 16) | (static_cast<unsigned char>(data[i + 1]) << 8) |
                 static_cast<unsigned char>(data[i + 2]);
    out += kBase64[(v >> 18) & 63];
    out += kBase64[(v >> 12) & 63];
    out += kBase64[(v >> 6) & 63];
    out += kBase64[v & 63];
    i += 3;
  }
  if (i + 1 == data.size())
  {
    unsigned v = static_cast<unsigned char>(data[i]) << 16;
    out += kBase64[(v >> 18) & 63];
    out += kBase64[(v >> 12) & 63];
    out += "==";
  }
  else if (i + 2 == data.size())
  {
    unsigned v = (static_cast<unsigned char>(data[i]) << 16) | (static_cast<unsigned char>(data[i + 1]) << 8);
    out += kBase64[(v >> 18) & 63];
    out += kBase64[(v >> 12) & 63];
    out += kBase64[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

bool base64Decode(const std::string& text, std::vector<char>& out)
{
  unsigned acc = 0;
  int bits = 0;
  for (char c : text)
  {
    if (c == '=' || c == ' ' || c == '\n' || c == '\r' || c == '\t')
      continue;
    const char* p = std::strchr(kBase64, c);
    if (!p || !*p)
      return false;
    acc = (acc << 6) | static_cast<unsigned>(p - kBase64);
    bits += 6;
    if (bits >= 8)
    {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xFF));
    }
  }
  return true;
}

std::string xmlEscape(const std::string& s)
{
  std::string out;
  for (char c : s)
  {
    switch (c)
    {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string xmlUnescape(const std::string& s)
{
  std::string out;
  for (size_t i = 0; i < s.size(); ++i)
  {
    if (s[i] == '&')
    {
      static const char* names[] = {"&lt;", "&gt;", "&amp;", "&quot;", "&apos;"};
      static const char chars[] = {'<', '>', '&', '"', '\''};
      bool done = false;
      for (int k = 0; k < 5 && !done; ++k)
      {
        size_t n = std::strlen(names[k]);
        if (s.compare(i, n, names[k]) == 0)
        {
          out += chars[k];
          i += n - 1;
          done = true;
        }
      }
      if (!done)
        out += '&';
    }
    else
    {
      out += s[i];
    }
  }
  return out;
}

// A small reader for XML-RPC <value> texts: tags, text between them.
struct XmlCursor
{
  const std::string& xml;
  size_t pos;

  void skipSpace()
  {
    while (pos < xml.size() && std::isspace(static_cast<unsigned char>(xml[pos])))
      ++pos;
  }
  /// Consumes <tag> (or <tag/>: `empty` set); false if the next tag is another.
  bool open(const char* tag, bool* empty = 0)
  {
    skipSpace();
    std::string a = std::string("<") + tag + ">";
    std::string b = std::string("<") + tag + "/>";
    if (xml.compare(pos, a.size(), a) == 0)
    {
      pos += a.size();
      if (empty)
        *empty = false;
      return true;
    }
    if (empty && xml.compare(pos, b.size(), b) == 0)
    {
      pos += b.size();
      *empty = true;
      return true;
    }
    return false;
  }
  bool close(const char* tag)
  {
    skipSpace();
    std::string a = std::string("</") + tag + ">";
    if (xml.compare(pos, a.size(), a) != 0)
      return false;
    pos += a.size();
    return true;
  }
  /// The text up to the next '<'.
  std::string text()
  {
    size_t end = xml.find('<', pos);
    if (end == std::string::npos)
      end = xml.size();
    std::string out = xml.substr(pos, end - pos);
    pos = end;
    return out;
  }
  bool peekClose(const char* tag)
  {
    size_t save = pos;
    bool r = close(tag);
    pos = save;
    return r;
  }
};

bool parseValue(XmlCursor& c, XmlRpcValue& out);

bool parseScalar(XmlCursor& c, XmlRpcValue& out)
{
  bool empty = false;
  if (c.open("boolean"))
  {
    out = XmlRpcValue(std::atoi(c.text().c_str()) != 0);
    return c.close("boolean");
  }
  if (c.open("int") || c.open("i4"))
  {
    std::string t = c.text();
    out = XmlRpcValue(static_cast<int>(std::strtol(t.c_str(), 0, 10)));
    return c.close("int") || c.close("i4");
  }
  if (c.open("double"))
  {
    out = XmlRpcValue(std::strtod(c.text().c_str(), 0));
    return c.close("double");
  }
  if (c.open("string", &empty))
  {
    if (empty)
    {
      out = XmlRpcValue(std::string());
      return true;
    }
    out = XmlRpcValue(xmlUnescape(c.text()));
    return c.close("string");
  }
  if (c.open("dateTime.iso8601"))
  {
    struct tm t = {};
    std::string s = c.text();
    if (std::sscanf(s.c_str(), "%4d%2d%2dT%2d:%2d:%2d", &t.tm_year, &t.tm_mon, &t.tm_mday, &t.tm_hour, &t.tm_min,
                    &t.tm_sec) != 6)
      return false;
    out = XmlRpcValue(&t);
    return c.close("dateTime.iso8601");
  }
  if (c.open("base64"))
  {
    std::vector<char> data;
    if (!base64Decode(c.text(), data))
      return false;
    out = XmlRpcValue(data.empty() ? static_cast<void*>(0) : data.data(), static_cast<int>(data.size()));
    return c.close("base64");
  }
  if (c.open("array"))
  {
    if (!c.open("data"))
      return false;
    out.setSize(0);
    int i = 0;
    while (!c.peekClose("data"))
    {
      XmlRpcValue item;
      if (!parseValue(c, item))
        return false;
      out.setSize(i + 1);
      out[i++] = item;
    }
    return c.close("data") && c.close("array");
  }
  if (c.open("struct"))
  {
    out.begin();
    while (c.open("member"))
    {
      if (!c.open("name"))
        return false;
      std::string name = xmlUnescape(c.text());
      if (!c.close("name"))
        return false;
      XmlRpcValue item;
      if (!parseValue(c, item))
        return false;
      out[name] = item;
      if (!c.close("member"))
        return false;
    }
    return c.close("struct");
  }
  // bare text: a string
  out = XmlRpcValue(xmlUnescape(c.text()));
  return true;
}

bool parseValue(XmlCursor& c, XmlRpcValue& out)
{
  bool empty = false;
  if (!c.open("value", &empty))
    return false;
  if (empty)
  {
    out = XmlRpcValue(std::string());
    return true;
  }
  if (!parseScalar(c, out))
    return false;
  return c.close("value");
}

}  // namespace

void XmlRpcValue::invalidate()
{
  switch (_type)
  {
    case TypeString:
      delete _value.asString;
      break;
    case TypeDateTime:
      delete _value.asTime;
      break;
    case TypeBase64:
      delete _value.asBinary;
      break;
    case TypeArray:
      delete _value.asArray;
      break;
    case TypeStruct:
      delete _value.asStruct;
      break;
    default:
      break;
  }
  _type = TypeInvalid;
  _value.asBinary = 0;
}

void XmlRpcValue::assertTypeOrInvalid(Type t) const
{
  if (_type != t)
    throw XmlRpcException("type error");
}

void XmlRpcValue::assertTypeOrInvalid(Type t)
{
  if (_type == TypeInvalid)
  {
    _type = t;
    switch (_type)
    {
      case TypeString:
        _value.asString = new std::string();
        break;
      case TypeDateTime:
        _value.asTime = new struct tm();
        break;
      case TypeBase64:
        _value.asBinary = new BinaryData();
        break;
      case TypeArray:
        _value.asArray = new ValueArray();
        break;
      case TypeStruct:
        _value.asStruct = new ValueStruct();
        break;
      default:
        _value.asBinary = 0;
        break;
    }
  }
  else if (_type != t)
  {
    throw XmlRpcException("type error");
  }
}

void XmlRpcValue::assertArray(int size) const
{
  if (_type != TypeArray)
    throw XmlRpcException("type error: expected an array");
  if (static_cast<int>(_value.asArray->size()) < size)
    throw XmlRpcException("range error: array index too large");
}

void XmlRpcValue::assertArray(int size)
{
  if (_type == TypeInvalid)
  {
    _type = TypeArray;
    _value.asArray = new ValueArray(size);
  }
  else if (_type == TypeArray)
  {
    if (static_cast<int>(_value.asArray->size()) < size)
      _value.asArray->resize(size);
  }
  else
  {
    throw XmlRpcException("type error: expected an array");
  }
}

void XmlRpcValue::assertStruct() const
{
  if (_type != TypeStruct)
    throw XmlRpcException("type error: expected a struct");
}

void XmlRpcValue::assertStruct()
{
  if (_type == TypeInvalid)
  {
    _type = TypeStruct;
    _value.asStruct = new ValueStruct();
  }
  else if (_type != TypeStruct)
  {
    throw XmlRpcException("type error: expected a struct");
  }
}

XmlRpcValue& XmlRpcValue::operator=(XmlRpcValue const& rhs)
{
  if (this == &rhs)
    return *this;
  invalidate();
  _type = rhs._type;
  switch (_type)
  {
    case TypeBoolean:
      _value.asBool = rhs._value.asBool;
      break;
    case TypeInt:
      _value.asInt = rhs._value.asInt;
      break;
    case TypeDouble:
      _value.asDouble = rhs._value.asDouble;
      break;
    case TypeDateTime:
      _value.asTime = new struct tm(*rhs._value.asTime);
      break;
    case TypeString:
      _value.asString = new std::string(*rhs._value.asString);
      break;
    case TypeBase64:
      _value.asBinary = new BinaryData(*rhs._value.asBinary);
      break;
    case TypeArray:
      _value.asArray = new ValueArray(*rhs._value.asArray);
      break;
    case TypeStruct:
      _value.asStruct = new ValueStruct(*rhs._value.asStruct);
      break;
    default:
      _value.asBinary = 0;
      break;
  }
  return *this;
}

bool XmlRpcValue::operator==(XmlRpcValue const& other) const
{
  if (_type != other._type)
    return false;
  switch (_type)
  {
    case TypeBoolean:
      return (!_value.asBool && !other._value.asBool) || (_value.asBool && other._value.asBool);
    case TypeInt:
      return _value.asInt == other._value.asInt;
    case TypeDouble:
      return _value.asDouble == other._value.asDouble;
    case TypeDateTime:
    {
      const struct tm& a = *_value.asTime;
      const struct tm& b = *other._value.asTime;
      return a.tm_sec == b.tm_sec && a.tm_min == b.tm_min && a.tm_hour == b.tm_hour && a.tm_mday == b.tm_mday &&
             a.tm_mon == b.tm_mon && a.tm_year == b.tm_year && a.tm_wday == b.tm_wday && a.tm_yday == b.tm_yday;
    }
    case TypeString:
      return *_value.asString == *other._value.asString;
    case TypeBase64:
      return *_value.asBinary == *other._value.asBinary;
    case TypeArray:
      return *_value.asArray == *other._value.asArray;
    case TypeStruct:
    {
      if (_value.asStruct->size() != other._value.asStruct->size())
        return false;
      ValueStruct::const_iterator a = _value.asStruct->begin();
      ValueStruct::const_iterator b = other._value.asStruct->begin();
      for (; a != _value.asStruct->end(); ++a, ++b)
        if (a->first != b->first || !(a->second == b->second))
          return false;
      return true;
    }
    default:
      return true;  // both invalid
  }
}

bool XmlRpcValue::operator!=(XmlRpcValue const& other) const
{
  return !(*this == other);
}

int XmlRpcValue::size() const
{
  switch (_type)
  {
    case TypeString:
      return static_cast<int>(_value.asString->size());
    case TypeBase64:
      return static_cast<int>(_value.asBinary->size());
    case TypeArray:
      return static_cast<int>(_value.asArray->size());
    case TypeStruct:
      return static_cast<int>(_value.asStruct->size());
    default:
      break;
  }
  throw XmlRpcException("type error");
}

bool XmlRpcValue::hasMember(const std::string& name) const
{
  return _type == TypeStruct && _value.asStruct->find(name) != _value.asStruct->end();
}

bool XmlRpcValue::fromXml(std::string const& valueXml, int* offset)
{
  if (!offset || *offset < 0 || static_cast<size_t>(*offset) > valueXml.size())
    return false;
  XmlCursor c = {valueXml, static_cast<size_t>(*offset)};
  XmlRpcValue v;
  if (!parseValue(c, v))
    return false;
  *this = v;
  *offset = static_cast<int>(c.pos);
  return true;
}

std::string XmlRpcValue::toXml() const
{
  std::ostringstream os;
  os << "<value>";
  switch (_type)
  {
    case TypeBoolean:
      os << "<boolean>" << (_value.asBool ? "1" : "0") << "</boolean>";
      break;
    case TypeInt:
      os << "<i4>" << _value.asInt << "</i4>";
      break;
    case TypeDouble:
    {
      char buf[64];
      std::snprintf(buf, sizeof(buf), _doubleFormat.c_str(), _value.asDouble);
      os << "<double>" << buf << "</double>";
      break;
    }
    case TypeString:
      os << xmlEscape(*_value.asString);
      break;
    case TypeDateTime:
    {
      char buf[32];
      const struct tm& t = *_value.asTime;
      std::snprintf(buf, sizeof(buf), "%4d%02d%02dT%02d:%02d:%02d", t.tm_year, t.tm_mon, t.tm_mday, t.tm_hour,
                    t.tm_min, t.tm_sec);
      os << "<dateTime.iso8601>" << buf << "</dateTime.iso8601>";
      break;
    }
    case TypeBase64:
      os << "<base64>" << base64Encode(*_value.asBinary) << "</base64>";
      break;
    case TypeArray:
      os << "<array><data>";
      for (const XmlRpcValue& v : *_value.asArray)
        os << v.toXml();
      os << "</data></array>";
      break;
    case TypeStruct:
      os << "<struct>";
      for (const auto& m : *_value.asStruct)
        os << "<member><name>" << xmlEscape(m.first) << "</name>" << m.second.toXml() << "</member>";
      os << "</struct>";
      break;
    default:
      break;
  }
  os << "</value>";
  return os.str();
}

std::ostream& XmlRpcValue::write(std::ostream& os) const
{
  switch (_type)
  {
    case TypeBoolean:
      os << _value.asBool;
      break;
    case TypeInt:
      os << _value.asInt;
      break;
    case TypeDouble:
      os << _value.asDouble;
      break;
    case TypeString:
      os << *_value.asString;
      break;
    case TypeDateTime:
    {
      char buf[32];
      const struct tm& t = *_value.asTime;
      std::snprintf(buf, sizeof(buf), "%4d%02d%02dT%02d:%02d:%02d", t.tm_year, t.tm_mon, t.tm_mday, t.tm_hour,
                    t.tm_min, t.tm_sec);
      os << buf;
      break;
    }
    case TypeBase64:
      os << base64Encode(*_value.asBinary);
      break;
    case TypeArray:
    {
      os << '{';
      for (size_t i = 0; i < _value.asArray->size(); ++i)
      {
        if (i > 0)
          os << ',';
        (*_value.asArray)[i].write(os);
      }
      os << '}';
      break;
    }
    case TypeStruct:
    {
      os << '[';
      for (ValueStruct::const_iterator it = _value.asStruct->begin(); it != _value.asStruct->end(); ++it)
      {
        if (it != _value.asStruct->begin())
          os << ',';
        os << it->first << ':';
        it->second.write(os);
      }
      os << ']';
      break;
    }
    default:
      break;
  }
  return os;
}

}  // namespace XmlRpc

std::ostream& operator<<(std::ostream& os, const XmlRpc::XmlRpcValue& v)
{
  return v.write(os);
}
