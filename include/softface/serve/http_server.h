#ifndef softface_serve_http_server_h
#define softface_serve_http_server_h

#include <ostream>
#include <string>

namespace softface
{
  namespace Serve
  {
    /// What the server asks of the application: no networking in here.
    class RequestHandler
    {
    public:
      struct Reply
      {
        unsigned int status = 200;
        std::string  content_type;
        std::string  body;
      };
      struct Message
      {
        bool        binary = false;
        std::string data;
      };

      virtual ~RequestHandler() = default;
      /// A GET of @p target (path and query).
      virtual Reply
      get(const std::string &target) = 0;
      /// A WebSocket text message; the answer goes back on the same socket.
      virtual Message
      message(const std::string &text) = 0;
    };

    /**
     * Serve HTTP GETs and WebSocket messages (Boost.Beast, one thread:
     * requests are answered in turn) on @p address : @p port (0: any free
     * port) until SIGINT or SIGTERM; once listening, "Serving on
     * http://address:port/" goes to @p out. Throws an Error if the address
     * cannot be bound.
     */
    void
    run_server(const std::string &address,
               const unsigned int port,
               RequestHandler    &handler,
               std::ostream      &out);
  } // namespace Serve
} // namespace softface

#endif
