# Demo, first part: pycomm3 prints the board's Identity object (class 0x01, instance 1).
# Usage: python -c PRELUDE+THIS BOARD_IP (xtask prepends identity.py).
ip = sys.argv[1]
wait_for_board(ip)
with CIPDriver(ip) as driver:
    print(f"Identity of {ip} (pycomm3, class 0x01 instance 1):")
    for attribute, _, label, text in read_identity(driver):
        print(f"  {attribute}  {label:<14} {text}")
