// ddes roscpp: the parts of xmlrpcpp a node uses (values and their exception); ddes speaks to
// its world through docs/external-nodes.md, so there is no XML-RPC client or server here.
#ifndef _XMLRPC_H_
#define _XMLRPC_H_

#include <stdexcept>
#include <string>

#include "xmlrpcpp/XmlRpcException.h"
#include "xmlrpcpp/XmlRpcValue.h"

#endif  // _XMLRPC_H_
