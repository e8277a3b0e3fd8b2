// ddes roscpp: XMLRPCPP_DECL (a static library: nothing to import or export).
#ifndef XMLRPCPP_DECL_H_INCLUDED
#define XMLRPCPP_DECL_H_INCLUDED
#define XMLRPCPP_DECL
#endif
