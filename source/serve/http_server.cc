// A small HTTP and WebSocket server (serve) on Boost.Beast: one thread, one
// io_context; GETs and WebSocket messages are handed to a RequestHandler.
// Kept free of deal.II so that this heavy translation unit compiles alone.

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <softface/core/error.h>
#include <softface/serve/http_server.h>

#include <csignal>
#include <memory>

namespace softface
{
  namespace Serve
  {
    namespace
    {
      namespace beast     = boost::beast;
      namespace http      = beast::http;
      namespace websocket = beast::websocket;
      namespace net       = boost::asio;
      using tcp           = net::ip::tcp;

      class WebSocketSession
          : public std::enable_shared_from_this<WebSocketSession>
      {
      public:
        WebSocketSession(tcp::socket &&socket, RequestHandler &handler)
            : stream(std::move(socket))
            , handler(handler)
        {}

        void
        start(http::request<http::string_body> request)
        {
          stream.set_option(websocket::stream_base::timeout::suggested(
            beast::role_type::server));
          // A plan is a few hundred bytes.
          stream.read_message_max(1 << 16);
          stream.async_accept(
            request,
            beast::bind_front_handler(&WebSocketSession::on_accept,
                                      shared_from_this()));
        }

      private:
        void
        on_accept(const beast::error_code error)
        {
          if (!error)
            read();
        }

        void
        read()
        {
          stream.async_read(buffer,
                            beast::bind_front_handler(
                              &WebSocketSession::on_read, shared_from_this()));
        }

        void
        on_read(const beast::error_code error, std::size_t)
        {
          if (error)
            return; // closed by the page, or the server stopping
          const std::string text = beast::buffers_to_string(buffer.data());
          buffer.consume(buffer.size());
          try
            {
              reply = handler.message(text);
            }
          catch (const std::exception &e)
            {
              reply = {false, std::string("{\"error\":\"server\"}")};
            }
          stream.binary(reply.binary);
          stream.async_write(
            net::buffer(reply.data),
            beast::bind_front_handler(&WebSocketSession::on_write,
                                      shared_from_this()));
        }

        void
        on_write(const beast::error_code error, std::size_t)
        {
          if (!error)
            read();
        }

        websocket::stream<beast::tcp_stream> stream;
        RequestHandler                      &handler;
        beast::flat_buffer                   buffer;
        RequestHandler::Message              reply;
      };

      class HttpSession : public std::enable_shared_from_this<HttpSession>
      {
      public:
        HttpSession(tcp::socket &&socket, RequestHandler &handler)
            : stream(std::move(socket))
            , handler(handler)
        {}

        void
        start()
        {
          read();
        }

      private:
        void
        read()
        {
          request = {};
          stream.expires_after(std::chrono::seconds(60));
          http::async_read(stream,
                           buffer,
                           request,
                           beast::bind_front_handler(&HttpSession::on_read,
                                                     shared_from_this()));
        }

        void
        on_read(const beast::error_code error, std::size_t)
        {
          if (error)
            {
              beast::error_code ignored;
              stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
              return;
            }
          // Re-plans on /replan, from the server's own page only: another
          // site open in the browser must not drive it (its Origin differs).
          const std::string origin(request[http::field::origin]);
          const bool        same_origin =
            origin.empty() ||
            origin == "http://" + std::string(request[http::field::host]);
          if (websocket::is_upgrade(request) && request.target() == "/replan" &&
              same_origin)
            {
              std::make_shared<WebSocketSession>(stream.release_socket(),
                                                 handler)
                ->start(std::move(request));
              return;
            }
          response = std::make_shared<http::response<http::string_body>>();
          response->version(request.version());
          response->keep_alive(request.keep_alive());
          response->set(http::field::server, "softface");
          response->set(http::field::cache_control, "no-store");
          RequestHandler::Reply reply;
          if (websocket::is_upgrade(request))
            reply = {403,
                     "text/plain",
                     "WebSockets: /replan, from this server's page only\n"};
          else if (request.method() != http::verb::get)
            reply = {405, "text/plain", "only GET is served\n"};
          else
            try
              {
                reply = handler.get(std::string(request.target()));
              }
            catch (const std::exception &e)
              {
                reply = {500, "text/plain", std::string(e.what()) + "\n"};
              }
          response->result(reply.status);
          response->set(http::field::content_type, reply.content_type);
          response->body() = std::move(reply.body);
          response->prepare_payload();
          http::async_write(stream,
                            *response,
                            beast::bind_front_handler(&HttpSession::on_write,
                                                      shared_from_this(),
                                                      response->need_eof()));
        }

        void
        on_write(const bool close, const beast::error_code error, std::size_t)
        {
          if (error)
            return;
          if (close)
            {
              beast::error_code ignored;
              stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
              return;
            }
          read();
        }

        beast::tcp_stream                                  stream;
        RequestHandler                                    &handler;
        beast::flat_buffer                                 buffer;
        http::request<http::string_body>                   request;
        std::shared_ptr<http::response<http::string_body>> response;
      };

      void
      accept(tcp::acceptor &acceptor, RequestHandler &handler)
      {
        acceptor.async_accept([&acceptor, &handler](const beast::error_code e,
                                                    tcp::socket socket) {
          if (e == net::error::operation_aborted)
            return;
          if (!e)
            std::make_shared<HttpSession>(std::move(socket), handler)->start();
          accept(acceptor, handler);
        });
      }
    } // namespace

    void
    run_server(const std::string &address,
               const unsigned int port,
               RequestHandler    &handler,
               std::ostream      &out)
    {
      net::io_context   io(1);
      beast::error_code error;
      const auto        ip = net::ip::make_address(address, error);
      if (error)
        throw Error("Serve/Address: '" + address + "' is not an IP address (" +
                    error.message() + ").");
      tcp::acceptor       acceptor(io);
      const tcp::endpoint endpoint(ip, static_cast<unsigned short>(port));
      acceptor.open(endpoint.protocol(), error);
      if (!error)
        acceptor.set_option(net::socket_base::reuse_address(true), error);
      if (!error)
        acceptor.bind(endpoint, error);
      if (!error)
        acceptor.listen(net::socket_base::max_listen_connections, error);
      if (error)
        throw Error("cannot listen on " + address + ":" + std::to_string(port) +
                    " (" + error.message() +
                    "); choose another Serve/Port, or 0 for any free one.");

      // Ctrl-C (or a kill) ends the loop: open sockets are dropped.
      net::signal_set signals(io, SIGINT, SIGTERM);
      signals.async_wait([&io](const beast::error_code, int) { io.stop(); });

      accept(acceptor, handler);
      out << "Serving on http://" << address << ':'
          << acceptor.local_endpoint().port() << "/ (Ctrl-C stops)"
          << std::endl;
      io.run();
      out << "softface serve: stopped" << std::endl;
    }
  } // namespace Serve
} // namespace softface
