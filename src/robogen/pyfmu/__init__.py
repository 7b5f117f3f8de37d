"""pyfmu"""
