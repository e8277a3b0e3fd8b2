// ddes roscpp: <XmlRpc.h>, as xmlrpcpp installs it beside <xmlrpcpp/XmlRpc.h>.
#include "xmlrpcpp/XmlRpc.h"
