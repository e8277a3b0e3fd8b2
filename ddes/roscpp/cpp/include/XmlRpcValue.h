// ddes roscpp: <XmlRpcValue.h>, as xmlrpcpp installs it beside <xmlrpcpp/XmlRpcValue.h>.
#include "xmlrpcpp/XmlRpcValue.h"
