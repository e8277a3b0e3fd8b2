// ddes roscpp: XmlRpc::XmlRpcValue, a parameter value (xmlrpcpp's API).
//
// A value is invalid, a bool, an int, a double, a string, a date-time (struct tm), binary
// data (base64), an array or a struct (string keys, sorted).  Conversions throw
// XmlRpcException("type error") when the value holds another type; an invalid value becomes
// the requested type on first use (operator[](int) makes it an array, operator[](string) a
// struct, the non-const conversions the scalar), as in xmlrpcpp.  Parameters travel to and from
// the ddes world as the tagged values of docs/external-nodes.md.
#ifndef _XMLRPCVALUE_H_
#define _XMLRPCVALUE_H_

#include <ctime>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "xmlrpcpp/XmlRpcDecl.h"

namespace XmlRpc
{

class XMLRPCPP_DECL XmlRpcValue
{
public:
  enum Type
  {
    TypeInvalid,
    TypeBoolean,
    TypeInt,
    TypeDouble,
    TypeString,
    TypeDateTime,
    TypeBase64,
    TypeArray,
    TypeStruct
  };

  typedef std::vector<char> BinaryData;
  typedef std::vector<XmlRpcValue> ValueArray;
  typedef std::map<std::string, XmlRpcValue> ValueStruct;
  typedef ValueStruct::iterator iterator;
  typedef ValueStruct::const_iterator const_iterator;

  XmlRpcValue() : _type(TypeInvalid) { _value.asBinary = 0; }
  XmlRpcValue(bool value) : _type(TypeBoolean) { _value.asBool = value; }
  XmlRpcValue(int value) : _type(TypeInt) { _value.asInt = value; }
  XmlRpcValue(double value) : _type(TypeDouble) { _value.asDouble = value; }
  XmlRpcValue(std::string const& value) : _type(TypeString) { _value.asString = new std::string(value); }
  XmlRpcValue(const char* value) : _type(TypeString) { _value.asString = new std::string(value); }
  XmlRpcValue(struct tm* value) : _type(TypeDateTime) { _value.asTime = new struct tm(*value); }
  XmlRpcValue(void* value, int nBytes) : _type(TypeBase64)
  {
    _value.asBinary = new BinaryData(static_cast<char*>(value), static_cast<char*>(value) + nBytes);
  }
  /// Parses the <value> element at *offset of an XML-RPC text (invalid if it is not one).
  XmlRpcValue(std::string const& xml, int* offset) : _type(TypeInvalid)
  {
    _value.asBinary = 0;
    if (!fromXml(xml, offset))
      _type = TypeInvalid;
  }
  XmlRpcValue(XmlRpcValue const& rhs) : _type(TypeInvalid) { _value.asBinary = 0; *this = rhs; }
  ~XmlRpcValue() { invalidate(); }

  /// Back to the invalid value.
  void clear() { invalidate(); }

  XmlRpcValue& operator=(XmlRpcValue const& rhs);
  XmlRpcValue& operator=(bool const& rhs) { return operator=(XmlRpcValue(rhs)); }
  XmlRpcValue& operator=(int const& rhs) { return operator=(XmlRpcValue(rhs)); }
  XmlRpcValue& operator=(double const& rhs) { return operator=(XmlRpcValue(rhs)); }
  XmlRpcValue& operator=(const char* rhs) { return operator=(XmlRpcValue(std::string(rhs))); }

  bool operator==(XmlRpcValue const& other) const;
  bool operator!=(XmlRpcValue const& other) const;

  operator bool&() { assertTypeOrInvalid(TypeBoolean); return _value.asBool; }
  operator int&() { assertTypeOrInvalid(TypeInt); return _value.asInt; }
  operator double&() { assertTypeOrInvalid(TypeDouble); return _value.asDouble; }
  operator std::string&() { assertTypeOrInvalid(TypeString); return *_value.asString; }
  operator BinaryData&() { assertTypeOrInvalid(TypeBase64); return *_value.asBinary; }
  operator struct tm&() { assertTypeOrInvalid(TypeDateTime); return *_value.asTime; }

  operator const bool&() const { assertTypeOrInvalid(TypeBoolean); return _value.asBool; }
  operator const int&() const { assertTypeOrInvalid(TypeInt); return _value.asInt; }
  operator const double&() const { assertTypeOrInvalid(TypeDouble); return _value.asDouble; }
  operator const std::string&() const { assertTypeOrInvalid(TypeString); return *_value.asString; }
  operator const BinaryData&() const { assertTypeOrInvalid(TypeBase64); return *_value.asBinary; }
  operator const struct tm&() const { assertTypeOrInvalid(TypeDateTime); return *_value.asTime; }

  XmlRpcValue const& operator[](int i) const { assertArray(i + 1); return _value.asArray->at(i); }
  XmlRpcValue& operator[](int i) { assertArray(i + 1); return _value.asArray->at(i); }

  XmlRpcValue& operator[](std::string const& k) const { assertStruct(); return (*_value.asStruct)[k]; }
  XmlRpcValue& operator[](std::string const& k) { assertStruct(); return (*_value.asStruct)[k]; }
  XmlRpcValue& operator[](const char* k) const { assertStruct(); return (*_value.asStruct)[std::string(k)]; }
  XmlRpcValue& operator[](const char* k) { assertStruct(); return (*_value.asStruct)[std::string(k)]; }

  iterator begin() { assertStruct(); return _value.asStruct->begin(); }
  iterator end() { assertStruct(); return _value.asStruct->end(); }
  const_iterator begin() const { assertStruct(); return _value.asStruct->begin(); }
  const_iterator end() const { assertStruct(); return _value.asStruct->end(); }

  bool valid() const { return _type != TypeInvalid; }
  Type const& getType() const { return _type; }
  /// Characters of a string, bytes of binary data, items of an array, members of a struct.
  int size() const;
  /// Makes the value an array of at least `size` items.
  void setSize(int size) { assertArray(size); }
  bool hasMember(const std::string& name) const;

  bool fromXml(std::string const& valueXml, int* offset);
  std::string toXml() const;
  /// xmlrpcpp's text: arrays as {a,b}, structs as [k:v,...].
  std::ostream& write(std::ostream& os) const;

  static std::string const& getDoubleFormat() { return _doubleFormat; }
  static void setDoubleFormat(const char* f) { _doubleFormat = f; }

protected:
  void invalidate();
  void assertTypeOrInvalid(Type t) const;
  void assertTypeOrInvalid(Type t);
  void assertArray(int size) const;
  void assertArray(int size);
  void assertStruct() const;
  void assertStruct();

  static std::string _doubleFormat;

  Type _type;
  union
  {
    bool asBool;
    int asInt;
    double asDouble;
    struct tm* asTime;
    std::string* asString;
    BinaryData* asBinary;
    ValueArray* asArray;
    ValueStruct* asStruct;
  } _value;
};

}  // namespace XmlRpc

XMLRPCPP_DECL std::ostream& operator<<(std::ostream& os, const XmlRpc::XmlRpcValue& v);

#endif  // _XMLRPCVALUE_H_
