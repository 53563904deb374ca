"""`cargo xtask demo`, first part: pycomm3 prints the board's Identity object (class 0x01,
instance 1).

Usage: python demo_identity.py BOARD_IP
"""
import sys

from pycomm3 import CIPDriver

from identity import read_identity, wait_for_board

ip = sys.argv[1]
wait_for_board(ip)
with CIPDriver(ip) as driver:
    print(f"Identity of {ip} (pycomm3, class 0x01 instance 1):")
    for attribute, _, label, text in read_identity(driver):
        print(f"  {attribute}  {label:<14} {text}")
