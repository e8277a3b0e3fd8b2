// ddes roscpp: <XmlRpcException.h>, as xmlrpcpp installs it beside <xmlrpcpp/XmlRpcException.h>.
#include "xmlrpcpp/XmlRpcException.h"
