"""pyserial URL handlers of roboscript (pyserial imports ``protocol_<scheme>`` from here)."""
