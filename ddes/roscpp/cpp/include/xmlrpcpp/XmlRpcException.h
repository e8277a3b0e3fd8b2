// ddes roscpp: XmlRpc::XmlRpcException, what XmlRpcValue throws on a type or range error.
// As in xmlrpcpp it is not a std::exception: catch it by its own type.
#ifndef _XMLRPCEXCEPTION_H_
#define _XMLRPCEXCEPTION_H_

#include <string>

#include "xmlrpcpp/XmlRpcDecl.h"

namespace XmlRpc
{

class XMLRPCPP_DECL XmlRpcException
{
public:
  XmlRpcException(const std::string& message, int code = -1) : _message(message), _code(code) {}
  const std::string& getMessage() const { return _message; }
  int getCode() const { return _code; }

private:
  std::string _message;
  int _code;
};

}  // namespace XmlRpc

#endif  // _XMLRPCEXCEPTION_H_
